# Tests of pnf::estimate_data, pnf::choose_filter_params and `pnf filter --auto` / --stop-change:
# included into the single test executable (the CLI cases skip when PNF_CLI_PATH is empty).
# auto_params_test: the estimators; choose_filter_params_test: the rule and `pnf filter --auto`;
# auto_params_creases_test: issue 14 (rare creases, choices independent of the density);
# auto_row_order_test: the same estimate, choice and normals whatever the input's row order;
# crease_evidence_test: the crease measure of lib/src/auto/crease_evidence.hpp by itself;
# independent_errors_test: the gate that adds the independent-errors setting to the judged passes;
# judged_pass_budget_test: the settings the judge tries and the passes it may run; noisy_fallback_test: the one wide pass
# tried on noisy positions where the judged settings keep the input; judge_arithmetic_test: the judge's vector exp and sums; stein_risk_test: Stein's risk estimate,
# the noise it takes and the passes it keeps; unseen_gains_test: the input kept where the judge cannot see a pass's
# gain on noisy positions; held_out_planes_test: the held-out check's score; sample_neighbourhoods_test: the samples'
# searches the estimate and the judge share; auto_real_meshes_test: --auto on the
# team's meshes where it once did harm or where a judged setting gains;
# real_meshes_test, mesh_reader_test: the true normals of pnf_eval_real's meshes and point sets,
# and its readers (bench/real_meshes.hpp, compiled in here with eval_clouds.cpp, which it builds on).
list(APPEND PNF_TEST_SOURCES
  ${PROJECT_SOURCE_DIR}/tests/auto/auto_params_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/auto_params_creases_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/auto_row_order_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/choose_filter_params_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/crease_evidence_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/independent_errors_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/judged_pass_budget_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/surface_judge_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/noisy_fallback_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/judge_arithmetic_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/stein_risk_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/unseen_gains_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/held_out_planes_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/sample_neighbourhoods_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/real_meshes_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/auto_real_meshes_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/mesh_reader_test.cpp
  ${PROJECT_SOURCE_DIR}/bench/real_meshes.cpp
  ${PROJECT_SOURCE_DIR}/bench/mesh_reader.cpp
  ${PROJECT_SOURCE_DIR}/bench/eval_clouds.cpp)
set_source_files_properties(${PROJECT_SOURCE_DIR}/tests/auto/real_meshes_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/auto_real_meshes_test.cpp
  ${PROJECT_SOURCE_DIR}/tests/auto/mesh_reader_test.cpp PROPERTIES INCLUDE_DIRECTORIES ${PROJECT_SOURCE_DIR}/bench)
