# Surfel renderer and PNG writer (pnf/render.hpp, pnf/png.hpp): included into the pnf library
# target, which links libpng (PNG::PNG).
list(APPEND PNF_RENDER_SOURCES
  ${PROJECT_SOURCE_DIR}/lib/src/render/render.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/render/render_options.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/render/colour_bar.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/render/png.cpp)
