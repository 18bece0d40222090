# glcheck scene --time: the side-by-side table is printed for every method, and the bits it was
# timed on are oitref's frame as `oitref render` makes it on its own (same scene, size, profile),
# so a speed-up reported there cannot come from changed bits. 1 and 2 threads give the same hash.
set(common ${SCENE} --size 96x54 --profile llvmpipe)
execute_process(COMMAND ${OITREF} glcheck scene ${common} --methods opaque,wsum --threads 2 --time 2
                RESULT_VARIABLE s OUTPUT_VARIABLE timed ERROR_VARIABLE e)
if(NOT s EQUAL 0)
  message(FATAL_ERROR "glcheck scene --time failed (${s}):\n${timed}\n${e}")
endif()
# Ten figures a row: wall min, wall median and CPU median for each side, the two ratios of the
# medians and the two medians of the runs' own ratios ("pairs ×").
if(NOT timed MATCHES "CPU × wall × pairs × +wall ")
  message(FATAL_ERROR "the timing table lacks the paired ratios:\n${timed}")
endif()
string(REPEAT " +[0-9]+\\.[0-9]+" 10 ten)
foreach(method opaque wsum)
  execute_process(COMMAND ${OITREF} render ${common} --method ${method} --threads 1 OUTPUT_VARIABLE rendered RESULT_VARIABLE r)
  string(REGEX MATCH "pixels sha256 ([0-9a-f]+)" _ "${rendered}")
  string(SUBSTRING "${CMAKE_MATCH_1}" 0 16 hash)
  if(NOT r EQUAL 0 OR hash STREQUAL "" OR NOT timed MATCHES "\n  ${method}${ten} +${hash}\n")
    message(FATAL_ERROR "${method}: the timed row does not carry oitref render's hash '${hash}':\n${timed}")
  endif()
endforeach()
# One thread count for both renderers, or an error naming both.
execute_process(COMMAND ${CMAKE_COMMAND} -E env LP_NUM_THREADS=3 ${OITREF} glcheck scene ${common} --methods opaque --threads 2 --time 1
                RESULT_VARIABLE s ERROR_VARIABLE e OUTPUT_QUIET)
if(s EQUAL 0 OR NOT e MATCHES "--threads 2 but LP_NUM_THREADS=3")
  message(FATAL_ERROR "a conflicting LP_NUM_THREADS was not refused (${s}): ${e}")
endif()
