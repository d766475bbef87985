# The installable library: installs the build into a temporary prefix with `cmake --install`, then
# configures, builds and runs packaging/examples/ against that prefix alone (find_package(LodForge)), and runs the
# installed `lodforge` with a shipped preset, which it must find under its own prefix.
# -DSOURCE_DIR -DBUILD_DIR -DWORK_DIR -DMESH (a small textured OBJ)
file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

run("cmake --install" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${prefix}")
foreach(f include/lodforge/mesh.h include/lodforge/octree/octree_build.h include/lodforge/pack/preset_levels.h
          include/lodforge/runtime/lodstrips_runtime.h include/lodforge/runtime/morph_lodstrips_runtime.h
          lib/liblodforge_core.a lib/cmake/LodForge/LodForgeConfig.cmake
          lib/cmake/LodForge/LodForgeConfigVersion.cmake share/lodforge/presets/mobile.json)
  if(NOT EXISTS "${prefix}/${f}")
    message(FATAL_ERROR "${f} was not installed into ${prefix}")
  endif()
endforeach()

# The examples see only the installed prefix (no package registry, no build tree).
run("configuring packaging/examples/" "${CMAKE_COMMAND}" -S "${SOURCE_DIR}/packaging/examples" -B "${WORK_DIR}/examples" -G Ninja
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
run("building packaging/examples/" "${CMAKE_COMMAND}" --build "${WORK_DIR}/examples")

run("simplify_mesh" "${WORK_DIR}/examples/simplify_mesh" "${MESH}" "${WORK_DIR}/half.ply" 0.5)
if(NOT out MATCHES "^([0-9]+) -> ([0-9]+)")
  message(FATAL_ERROR "simplify_mesh printed: ${out}")
endif()
math(EXPR twice "${CMAKE_MATCH_2} * 2")
if(NOT EXISTS "${WORK_DIR}/half.ply" OR twice GREATER "${CMAKE_MATCH_1}" OR CMAKE_MATCH_2 LESS 100)
  message(FATAL_ERROR "simplify_mesh did not halve the mesh: ${out}")
endif()

# The installed CLI finds the shipped presets under its prefix; its .lodstrips plays in the runtime example.
run("installed lodforge strips --preset mobile" "${prefix}/bin/lodforge" --quiet strips "${MESH}"
    -o "${WORK_DIR}/mesh.lodstrips" --preset mobile)
run("play_lodstrips" "${WORK_DIR}/examples/play_lodstrips" "${WORK_DIR}/mesh.lodstrips")
if(NOT out MATCHES "^([0-9]+) ([0-9]+) ([0-9]+)")
  message(FATAL_ERROR "play_lodstrips printed: ${out}")
endif()
if(NOT CMAKE_MATCH_1 GREATER CMAKE_MATCH_2 OR NOT CMAKE_MATCH_2 GREATER CMAKE_MATCH_3)
  message(FATAL_ERROR "levels do not get coarser: ${out}")
endif()
file(REMOVE_RECURSE "${WORK_DIR}")
message(STATUS "installed package ok: ${out}")
