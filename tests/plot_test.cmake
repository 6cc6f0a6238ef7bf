# Runs the CubeSat example and docs/plot_results.py on it; fails unless the PNGs exist.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${RADNET} run ${SOURCE}/cases/examples/cubesat-3u.yaml -o ${WORK}/cubesat.h5 -q
                RESULT_VARIABLE run_rc OUTPUT_QUIET)
if(NOT run_rc EQUAL 0)
  message(FATAL_ERROR "radnet run failed: ${run_rc}")
endif()
execute_process(COMMAND /usr/bin/python3 ${SOURCE}/docs/plot_results.py ${WORK}/cubesat.h5 ${WORK}
                RESULT_VARIABLE plot_rc OUTPUT_VARIABLE plot_out ERROR_VARIABLE plot_err)
if(NOT plot_rc EQUAL 0)
  message(FATAL_ERROR "plot_results.py failed (${plot_rc}): ${plot_err}")
endif()
foreach(png cubesat_loads.png cubesat_eigenvalues.png)
  if(NOT EXISTS ${WORK}/${png})
    message(FATAL_ERROR "missing ${png}")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK})
