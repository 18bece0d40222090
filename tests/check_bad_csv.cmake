# Runs `oitref blend --cases` on a file with two bad lines and checks the messages name the line
# and column, that the good line still produced output, and that the exit status is 2 (an error:
# README, "Exit statuses").
execute_process(COMMAND ${OITREF} blend --cases ${CASES}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "expected exit status 2, got ${rc}")
endif()
if(NOT err MATCHES "line 3, column 5 \\(dst_rgb\\): unknown blend factor 'one_minus_srx_alpha'")
  message(FATAL_ERROR "missing line-3 message, got:\n${err}")
endif()
if(NOT err MATCHES "line 4, column 17 \\(src_g\\)")
  message(FATAL_ERROR "missing line-4 message, got:\n${err}")
endif()
if(NOT out MATCHES "rgba16f,add,add,src_alpha,one_minus_src_alpha,.*,3c00 3800 0000 3c00,38cd 3733 34cd 3c00,")
  message(FATAL_ERROR "the good line is missing from the output:\n${out}")
endif()
