# Point-file I/O (pnf/point_file.hpp): included into the pnf library target.
list(APPEND PNF_IO_SOURCES
  ${PROJECT_SOURCE_DIR}/lib/src/io/atomic_file.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/io/byte_source.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/io/pcd_header.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/io/pcd_reader.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/io/pcd_writer.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/io/ply_reader.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/io/ply_scalar.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/io/ply_writer.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/io/point_file.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/io/row_layout.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/io/text_points.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/io/vertex_fields.cpp
  ${PROJECT_SOURCE_DIR}/lib/src/io/write_target.cpp)
