# Runs oitref with ARGS ("|"-separated) and checks that it fails (non-zero exit status), that its
# error output contains EXPECT literally, and — when NO_FILE is given — that no such file was
# left behind (nothing half-written).
string(REPLACE "|" ";" args "${ARGS}")
if(NO_FILE)
  file(REMOVE "${NO_FILE}")
endif()
execute_process(COMMAND ${OITREF} ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "expected a non-zero exit status; output:\n${out}${err}")
endif()
string(FIND "${err}" "${EXPECT}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "expected the error to contain:\n  ${EXPECT}\ngot:\n${err}")
endif()
if(NO_FILE AND EXISTS "${NO_FILE}")
  message(FATAL_ERROR "a failed run left ${NO_FILE} behind")
endif()
