# Runs one case with 1 and with 2 threads and compares the two HDF5 files bit for bit
# (tests/compare_h5.py; timings excepted): every random stream is keyed by node and
# replica, so the thread count must not change a single bit of the result.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
foreach(threads 1 2)
  # One directory each: the file name is part of the result (/xdmf/series_file).
  file(MAKE_DIRECTORY ${WORK}/threads-${threads})
  execute_process(COMMAND ${RADNET} run ${CASE} -o ${WORK}/threads-${threads}/out.h5 -q --threads ${threads}
                  RESULT_VARIABLE rc OUTPUT_QUIET)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "radnet run --threads ${threads} failed: ${rc}")
  endif()
endforeach()
execute_process(COMMAND /usr/bin/python3 ${SOURCE}/tests/compare_h5.py ${WORK}/threads-1/out.h5 ${WORK}/threads-2/out.h5
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "results differ between 1 and 2 threads:\n${out}${err}")
endif()
file(REMOVE_RECURSE ${WORK})
