# Slurm: the batch scripts of jobs/ under a real single-node Slurm that the test starts itself
# (tests/drivers/slurm_cluster.sh); skipped (77) with the reason when Slurm cannot run here.
clothsim_add_script_test(slurm_chain slurm_chain.sh ${CMAKE_CURRENT_BINARY_DIR}/slurm_chain)
set_tests_properties(slurm_chain PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 240 PROCESSORS 2 RUN_SERIAL TRUE)
# The installed copy's jobs/main_job.sbatch under Slurm (3 steps of the main job's dress on 2 ranks, from outside
# the trees): tests/drivers/slurm_installed_main_job.sh.
clothsim_add_script_test(slurm_installed_main_job slurm_installed_main_job.sh ${CMAKE_CURRENT_BINARY_DIR}/slurm_installed_main_job)
set_tests_properties(slurm_installed_main_job PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 240 PROCESSORS 2 RUN_SERIAL TRUE)
