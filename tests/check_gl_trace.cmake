# Whole frames through a GL trace, on this machine's driver (llvmpipe in CI): glcheck scene records
# every GL call, oitref-gpu-capture replays the trace and writes what each read returned, and
# glcheck scene --gpu-reads must then print exactly the table of the direct run.
file(MAKE_DIRECTORY ${DIR})
set(args glcheck scene ${SCENE} --size 64x36 --profile llvmpipe --methods opaque,wsum,wboit,peel)
execute_process(COMMAND ${OITREF} ${args} --record-trace ${DIR}/frames.trace RESULT_VARIABLE s1 OUTPUT_VARIABLE direct ERROR_VARIABLE e1)
execute_process(COMMAND ${CAPTURE} frames ${DIR}/frames.trace ${DIR}/frames.reads RESULT_VARIABLE s2 ERROR_VARIABLE e2)
if(NOT s2 EQUAL 0)
  message(FATAL_ERROR "oitref-gpu-capture frames failed (${s2}):\n${e2}")
endif()
execute_process(COMMAND ${OITREF} ${args} --gpu-reads ${DIR}/frames.reads RESULT_VARIABLE s3 OUTPUT_VARIABLE replayed ERROR_VARIABLE e3)
string(REGEX REPLACE "\n(recording|GL texels)[^\n]*" "" direct "${direct}")
string(REGEX REPLACE "\n(recording|GL texels)[^\n]*" "" replayed "${replayed}")
if(NOT s1 EQUAL s3 OR NOT direct STREQUAL replayed OR NOT replayed MATCHES "scene squares")
  message(FATAL_ERROR "the replayed frames differ from the direct run (${s1}/${s3}):\n${direct}\n---\n${replayed}\n${e3}")
endif()
