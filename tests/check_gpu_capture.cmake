# oitref-gpu-capture on this machine's driver (Mesa's llvmpipe in CI) against oitref: the cases
# glcheck generates are captured by the standalone program, then `oitref blend --cases` compares
# the captured gpu_* columns with the llvmpipe profile, which glcheck blend holds to 100 %.
file(MAKE_DIRECTORY ${DIR})
execute_process(COMMAND ${OITREF} glcheck blend --generate 6000 --seed 11 --write-cases ${DIR}/cases.csv
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "glcheck blend failed (${status}):\n${out}")
endif()
execute_process(COMMAND ${CAPTURE} blend ${DIR}/cases.csv ${DIR}/captured.csv RESULT_VARIABLE status ERROR_VARIABLE out)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "oitref-gpu-capture failed (${status}):\n${out}")
endif()
execute_process(COMMAND ${OITREF} blend --cases ${DIR}/captured.csv --profile llvmpipe RESULT_VARIABLE status OUTPUT_VARIABLE out)
if(NOT status EQUAL 0 OR NOT out MATCHES "6000 cases with recorded texels" OR NOT out MATCHES "blended results bit-equal 100.00%")
  message(FATAL_ERROR "captured texels differ from oitref's llvmpipe profile (${status}):\n${out}")
endif()
