# The simulator's tests: sim_host's subcommands in process (sim_simulate) and as the executable.
est_add_test(sim_host_sample_motion LIBS sim_tools)
target_compile_definitions(test_sim_host_sample_motion PRIVATE SIM_HOST_EXE="$<TARGET_FILE:sim_host>")
add_dependencies(test_sim_host_sample_motion sim_host)
est_add_test(sim_host_simulate LIBS sim_simulate)
est_add_test(sim_host_simulate_ekf LIBS sim_simulate)
target_compile_definitions(test_sim_host_simulate_ekf PRIVATE SIM_HOST_EXE="$<TARGET_FILE:sim_host>")
add_dependencies(test_sim_host_simulate_ekf sim_host)
est_add_test(sim_host_learn_beam_model LIBS sim_simulate)
target_compile_definitions(test_sim_host_simulate PRIVATE SIM_HOST_EXE="$<TARGET_FILE:sim_host>")
add_dependencies(test_sim_host_simulate sim_host)
est_add_test(sim_team_diffdrive LIBS sim_team)
target_compile_definitions(test_sim_team_diffdrive PRIVATE SIM_HOST_EXE="$<TARGET_FILE:sim_host>")
add_dependencies(test_sim_team_diffdrive sim_host)
est_add_test(sim_team_coop LIBS sim_team)
target_compile_definitions(test_sim_team_coop PRIVATE SIM_HOST_EXE="$<TARGET_FILE:sim_host>"
                           ESTIMATOR_NODE_EXE="$<TARGET_FILE:estimator_node>")
target_link_libraries(test_sim_team_coop PRIVATE hal_lcm)
add_dependencies(test_sim_team_coop sim_host estimator_node)
# Real data (sim_host/data): each importer and evaluation on a short slice of its dataset, in process; skipped
# without ../shared/datasets (tests/support/datasets.hpp).
est_add_test(data_common LIBS sim_data)
foreach(format mrclam victoria carmen tricycle)
  est_add_test(data_${format} LIBS sim_data_${format})
endforeach()
est_add_test(progress LIBS sim_tools)
# sim_host plot (data/plot_log.hpp): a run's log plotted from the log alone.
est_add_test(plot_log LIBS sim_data sim_scenarios)
# Scenario files (sim/scenario_file.hpp): the parser, its refusals and the built-ins; `sim_host run` and `list`.
est_add_test(scenario_file LIBS sim_scenarios)
target_compile_definitions(test_scenario_file PRIVATE SIM_SCENARIOS_DIR="${PROJECT_SOURCE_DIR}/sim_host/scenarios")
est_add_test(sim_host_run LIBS sim_scenarios)
target_compile_definitions(test_sim_host_run PRIVATE SIM_HOST_EXE="$<TARGET_FILE:sim_host>"
                           ESTIMATOR_NODE_EXE="$<TARGET_FILE:estimator_node>")
target_link_libraries(test_sim_host_run PRIVATE hal_lcm)
add_dependencies(test_sim_host_run sim_host estimator_node)
# Campaigns (sim_host/campaign/): the aggregator's statistics and folders; sim_host sweep and aggregate end to end.
est_add_test(campaign_aggregate LIBS sim_campaign)
est_add_test(sim_host_sweep LIBS sim_campaign)
target_compile_definitions(test_sim_host_sweep PRIVATE SIM_HOST_EXE="$<TARGET_FILE:sim_host>")
add_dependencies(test_sim_host_sweep sim_host)
# The campaign on a single-node Slurm on localhost (tests/slurm/run-slurm-campaign: munged, slurmctld and slurmd
# started by the test in a temp folder); skipped without root, slurm-wlm, munge or jq.
add_test(NAME "slurm: the emitted job array on a single-node Slurm aggregates to the local sweep, seed for seed"
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/slurm/run-slurm-campaign $<TARGET_FILE_DIR:sim_host>)
set_tests_properties("slurm: the emitted job array on a single-node Slurm aggregates to the local sweep, seed for seed"
                     PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 120)
# sim_host run --live (sim/live_run.hpp): real time against estimator_node processes over udpm (~20 s; SERIAL, like
# the stamp alignment's test: real time against the nodes' clocks; skipped where udpm multicast does not work).
est_add_test(live_run SERIAL LIBS hal_lcm nlohmann_json::nlohmann_json)
target_compile_definitions(test_live_run PRIVATE SIM_HOST_EXE="$<TARGET_FILE:sim_host>")
add_dependencies(test_live_run sim_host estimator_node)
