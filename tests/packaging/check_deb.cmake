# Builds the .deb with CPack into OUT_DIR and checks what a user installs: both executables, the
# desktop entry (pointing at the studio and its icon), the icons, the shipped presets, the library with
# its headers and CMake package (docs/library.md), the Python module (docs/python.md), and dependencies
# from dpkg-shlibdeps.
file(REMOVE_RECURSE "${OUT_DIR}")
execute_process(COMMAND "${CPACK}" -G DEB -B "${OUT_DIR}" --config "${BUILD_DIR}/CPackConfig.cmake"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cpack failed (${rc}):\n${out}\n${err}")
endif()
file(GLOB debs "${OUT_DIR}/lodforge_*.deb")
list(LENGTH debs n)
if(NOT n EQUAL 1)
  message(FATAL_ERROR "expected one lodforge_*.deb in ${OUT_DIR}, found: ${debs}")
endif()
execute_process(COMMAND dpkg-deb -c "${debs}" OUTPUT_VARIABLE listing RESULT_VARIABLE rc)
foreach(path ./usr/bin/lodforge ./usr/bin/lodforge-studio ./usr/share/applications/lodforge-studio.desktop
             ./usr/share/icons/hicolor/256x256/apps/lodforge-studio.png
             ./usr/share/icons/hicolor/scalable/apps/lodforge-studio.svg
             ./usr/share/lodforge/samples/spot/spot_triangulated.obj
             ./usr/share/lodforge/presets/mobile.json ./usr/share/lodforge/presets/console.json
             ./usr/share/lodforge/presets/web.json ./usr/share/lodforge/presets/scan-archive.json
             ./usr/share/lodforge/engines/lodforge-babylon.mjs ./usr/share/lodforge/engines/lodforge-three.mjs
             ./usr/lib/liblodforge_core.a ./usr/lib/cmake/LodForge/LodForgeConfig.cmake
             ./usr/lib/cmake/LodForge/LodForgeConfigVersion.cmake ./usr/lib/cmake/LodForge/LodForgeTargets.cmake
             ./usr/include/lodforge/mesh.h ./usr/include/lodforge/io/mesh_io.h
             ./usr/include/lodforge/simplify/simplify.h ./usr/include/lodforge/pack/preset_levels.h
             ./usr/include/lodforge/runtime/lodstrips_runtime.h
             ./usr/include/lodforge/runtime/morph_lodstrips_runtime.h)
  string(FIND "${listing}" " ${path}\n" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${path} is missing from the package:\n${listing}")
  endif()
endforeach()
execute_process(COMMAND dpkg-deb -f "${debs}" Depends OUTPUT_VARIABLE depends)
foreach(dep libqt6widgets6 libvtk9.1 libtinygltf)
  string(FIND "${depends}" "${dep}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "Depends lacks ${dep}: ${depends}")
  endif()
endforeach()
execute_process(COMMAND dpkg-deb --fsys-tarfile "${debs}" COMMAND tar -xO ./usr/share/applications/lodforge-studio.desktop
                OUTPUT_VARIABLE desktop)
foreach(line "Exec=lodforge-studio" "Icon=lodforge-studio" "Type=Application")
  string(FIND "${desktop}" "${line}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "desktop entry lacks '${line}':\n${desktop}")
  endif()
endforeach()
# The Python module: in Debian's dist-packages, importable from the unpacked package, its presets found.
if(PYTHON)
  foreach(path ./usr/lib/python3/dist-packages/lodforge/__init__.py ./usr/lib/python3/dist-packages/lodforge/_core.pyi
               ./usr/lib/python3/dist-packages/lodforge/py.typed)
    string(FIND "${listing}" " ${path}\n" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "${path} is missing from the package:\n${listing}")
    endif()
  endforeach()
  foreach(dep python3-numpy "python3 (>= 3")
    string(FIND "${depends}" "${dep}" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "Depends lacks ${dep}: ${depends}")
    endif()
  endforeach()
  execute_process(COMMAND dpkg-deb -x "${debs}" "${OUT_DIR}/root" RESULT_VARIABLE rc)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env "PYTHONPATH=${OUT_DIR}/root/usr/lib/python3/dist-packages"
                          "LODFORGE_PRESETS_DIR=${OUT_DIR}/root/usr/share/lodforge/presets"
                          "${PYTHON}" -c "import lodforge; print(lodforge.__file__, lodforge.shipped_presets())"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(FIND "${out}" "${OUT_DIR}/root/usr/lib/python3/dist-packages/lodforge/__init__.py" at)
  string(FIND "${out}" "'mobile'" mobile)
  if(NOT rc EQUAL 0 OR at EQUAL -1 OR mobile EQUAL -1)
    message(FATAL_ERROR "the packaged Python module does not import (${rc}):\n${out}\n${err}")
  endif()
endif()
file(REMOVE_RECURSE "${OUT_DIR}")
message(STATUS "package ok: ${debs}")
