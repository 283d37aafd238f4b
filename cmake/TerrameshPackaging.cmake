# The version file of the CMake package, and the Debian package made by `cpack -G DEB` from the
# install rules: the CLI (bin/terramesh), the static libraries, their headers and CMake package,
# the robot profiles. Included at the end of the top-level CMakeLists.txt.
include(CMakePackageConfigHelpers)
write_basic_package_version_file("${CMAKE_CURRENT_BINARY_DIR}/terrameshConfigVersion.cmake"
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/terrameshConfigVersion.cmake"
  DESTINATION lib/cmake/terramesh)

set(CPACK_PACKAGE_NAME terramesh)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "terramesh maintainers <terramesh@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
  "Incremental manifold meshing of sparse SLAM maps, traversability and planning on the mesh")
set(CPACK_PACKAGE_DESCRIPTION
  "The terramesh command (mesh, bench, generate, eval) and the C++ libraries terramesh::mesher, \
datasets, traversability, planning and evaluation (static, with headers and a CMake package: \
find_package(terramesh)).")
set(CPACK_PACKAGE_INSTALL_DIRECTORY terramesh)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# The CLI's shared libraries (GMP, MPFR, yaml-cpp, GDAL, OMPL...) as dpkg-shlibdeps finds
# them, plus what a consumer of the CMake package compiles against: the headers of the public
# and link dependencies that terrameshConfig.cmake finds, and the libraries the static datasets
# library links (ROS bags: rosbag_storage, roscpp_serialization, class_loader...).
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS
  "libeigen3-dev (>= 3.3), libcgal-dev, libgmp-dev, libmpfr-dev, nlohmann-json3-dev (>= 3.10), \
libyaml-cpp-dev, libgdal-dev, libompl-dev, liboctomap-dev, libembree-dev, libnanoflann-dev, robin-map-dev, \
librosbag-storage-dev, libroscpp-core-dev, libclass-loader-dev")
include(CPack)
