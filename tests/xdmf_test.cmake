# Runs the hot/cold CubeSat (two orbit cases, two-sided panels) and the two-sided panel (no
# thermal model), then tests/check_xdmf.py on each result: every XDMF reference against the
# HDF5 file and, with -DPARAVIEW=ON, ParaView's three XDMF readers and a rendered PNG.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(extra "")
if(PARAVIEW)
  set(extra --paraview)
endif()
foreach(case examples/cubesat-hot-cold analytic/two-sided-panel)
  get_filename_component(stem ${case} NAME)
  execute_process(COMMAND ${RADNET} run ${SOURCE}/cases/${case}.yaml -o ${WORK}/${stem}.h5 -q
                  RESULT_VARIABLE run_rc OUTPUT_QUIET)
  if(NOT run_rc EQUAL 0)
    message(FATAL_ERROR "radnet run ${case} failed: ${run_rc}")
  endif()
  execute_process(COMMAND /usr/bin/python3 ${SOURCE}/tests/check_xdmf.py ${WORK}/${stem}.h5 ${extra}
                  RESULT_VARIABLE check_rc OUTPUT_VARIABLE check_out ERROR_VARIABLE check_err)
  message("${check_out}")
  if(NOT check_rc EQUAL 0)
    message(FATAL_ERROR "check_xdmf.py ${stem}.h5 failed (${check_rc}): ${check_err}")
  endif()
endforeach()
