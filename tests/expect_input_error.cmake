# Runs EXE with ARGS and checks the contract for bad input: exit status 2, exactly one line on
# stderr, containing EXPECTED. With LAUNCHER (e.g. mpirun;-np;2) the app's line is the first one;
# mpirun's own report of the exit status follows it.
execute_process(COMMAND ${LAUNCHER} ${EXE} ${ARGS} RESULT_VARIABLE status ERROR_VARIABLE err OUTPUT_VARIABLE out)
string(STRIP "${err}" err)
if(LAUNCHER)
  string(REGEX REPLACE "\n.*" "" err "${err}")
endif()
if(NOT status EQUAL 2)
  message(FATAL_ERROR "exit status ${status}, expected 2; stderr: ${err}")
endif()
string(FIND "${err}" "\n" newline)
if(NOT newline EQUAL -1)
  message(FATAL_ERROR "error message spans several lines:\n${err}")
endif()
string(FIND "${err}" "${EXPECTED}" found)
if(found EQUAL -1)
  message(FATAL_ERROR "stderr '${err}' does not contain '${EXPECTED}'")
endif()
