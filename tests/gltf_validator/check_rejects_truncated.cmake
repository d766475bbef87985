# Writes the first half of a valid GLB and expects the validator to report errors (exit 1).
execute_process(COMMAND ${NODE} -e "const fs=require('fs');const b=fs.readFileSync(process.argv[1]);fs.writeFileSync(process.argv[2],b.subarray(0,b.length>>1));" ${SOURCE} ${OUT}
                RESULT_VARIABLE wrote)
if(NOT wrote EQUAL 0)
  message(FATAL_ERROR "could not write ${OUT}")
endif()
execute_process(COMMAND ${NODE} ${SCRIPT} ${OUT} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1)
  message(FATAL_ERROR "validator accepted a truncated GLB (exit ${rc}):\n${out}${err}")
endif()
