# `lodforge-studio BROKEN --screenshot OUT` must fail cleanly: exit status 2, the problem on stderr naming
# the file, no PNG written, no dialog waiting for a click (the run would time out).
# Arguments: -DSTUDIO=<lodforge-studio> -DWORK_DIR=<scratch folder>
file(MAKE_DIRECTORY "${WORK_DIR}")
set(broken "${WORK_DIR}/truncated_for_screenshot.ply")
set(out "${WORK_DIR}/never_written.png")
file(REMOVE "${out}")
# A PLY cut off in the middle of its vertex list.
file(WRITE "${broken}" "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
                       "end_header\n0 0 0\n1 0 0\n1 1")
execute_process(COMMAND "${STUDIO}" "${broken}" --screenshot "${out}" --size 640x480
                RESULT_VARIABLE rc OUTPUT_VARIABLE out_text ERROR_VARIABLE err_text TIMEOUT 120)
message(STATUS "exit status: ${rc}\nstderr: ${err_text}")
if(NOT rc STREQUAL "2")
  message(FATAL_ERROR "expected exit status 2, got '${rc}'")
endif()
if(NOT err_text MATCHES "truncated_for_screenshot\\.ply")
  message(FATAL_ERROR "stderr does not name the file")
endif()
if(EXISTS "${out}")
  message(FATAL_ERROR "a screenshot was written for a file that failed to load")
endif()
