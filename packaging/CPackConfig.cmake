# `cpack -G DEB` in the build directory produces lodforge_<version>_<arch>.deb with both executables,
# the desktop entry and the icon, the shipped presets, and the library (static core, headers, CMake
# package: the install() rules of core/CMakeLists.txt). Runtime dependencies are computed from the binaries by dpkg-shlibdeps.
install(FILES ${PROJECT_SOURCE_DIR}/packaging/lodforge-studio.desktop DESTINATION share/applications)
install(FILES ${PROJECT_SOURCE_DIR}/packaging/lodforge.svg
        DESTINATION share/icons/hicolor/scalable/apps RENAME lodforge-studio.svg)
install(FILES ${PROJECT_SOURCE_DIR}/packaging/lodforge.png
        DESTINATION share/icons/hicolor/256x256/apps RENAME lodforge-studio.png)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/resources/samples/ DESTINATION share/lodforge/samples)
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION share/doc/lodforge RENAME copyright)

set(CPACK_PACKAGE_NAME lodforge)
set(CPACK_PACKAGE_VENDOR "LodForge")
set(CPACK_PACKAGE_CONTACT "LodForge developers <dev@lodforge.invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Level-of-detail authoring for heavy scanned and modelled meshes")
# Consumers of the CMake package link the static core's dependencies (LodForgeConfig.cmake finds them):
# their -dev packages are suggested, not required, for users of the programs alone.
set(CPACK_DEBIAN_PACKAGE_SUGGESTS
    "libeigen3-dev, libtinygltf-dev, libtinyobjloader-dev, nlohmann-json3-dev, libssl-dev, libmeshoptimizer-dev")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The Python module (lib/python3/dist-packages/lodforge) is built for the interpreter found at configure
# time and creates NumPy arrays; dpkg-shlibdeps cannot see either (an extension does not link libpython).
if(LODFORGE_PYTHON)
  math(EXPR _python_next_minor "${Python_VERSION_MINOR} + 1")
  set(CPACK_DEBIAN_PACKAGE_DEPENDS
      "python3 (>= ${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}), python3 (<< ${Python_VERSION_MAJOR}.${_python_next_minor}), python3-numpy")
endif()
# `compare --render` starts a private Xvfb on a machine without a display (docs/image-compare.md).
# lodforge.dask_batch runs on Dask (python3-distributed).
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "xvfb, python3-distributed")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
include(CPack)
