# Every third-party dependency is found here, once, as imported targets (Debian 12 packages; see
# scripts/install-deps.sh and the README for why each one is used).
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)
find_package(glm REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(fmt REQUIRED)
find_package(CLI11 REQUIRED)
pkg_check_modules(XXHASH REQUIRED IMPORTED_TARGET libxxhash)

# Heavy dependencies are only needed by bake/ (never by formats/ or runtime/).
find_package(embree 3 REQUIRED)
find_package(draco REQUIRED)
find_package(meshoptimizer CONFIG REQUIRED) # EXT_meshopt_compression (decoder; encoder in samples/)
pkg_check_modules(WEBP REQUIRED IMPORTED_TARGET libwebp) # EXT_texture_webp images
find_package(TBB REQUIRED)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)
find_path(TINYGLTF_INCLUDE_DIR tiny_gltf.h REQUIRED)
add_library(probebake_tinygltf INTERFACE)
target_include_directories(probebake_tinygltf SYSTEM INTERFACE "${TINYGLTF_INCLUDE_DIR}")
target_link_libraries(probebake_tinygltf INTERFACE nlohmann_json::nlohmann_json PkgConfig::STB)

# Debian's FindOpenVDB.cmake asks for Boost components (iostreams) that libopenvdb-dev does not pull in;
# the library itself needs only its headers, Boost headers and TBB, so import it directly.
find_path(OPENVDB_INCLUDE_DIR openvdb/openvdb.h REQUIRED)
find_library(OPENVDB_LIBRARY openvdb REQUIRED)
find_path(BOOST_INCLUDE_DIR boost/version.hpp REQUIRED)
find_package(Imath CONFIG REQUIRED) # OpenVDB's inline half-float conversions reference libImath
find_package(OpenEXR CONFIG REQUIRED) # reference images (probebake_reference)
add_library(probebake_openvdb INTERFACE)
target_include_directories(probebake_openvdb SYSTEM INTERFACE "${OPENVDB_INCLUDE_DIR}" "${BOOST_INCLUDE_DIR}")
target_link_libraries(probebake_openvdb INTERFACE "${OPENVDB_LIBRARY}" TBB::tbb Imath::Imath)

if(PROBEBAKE_BUILD_TESTS)
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()
if(PROBEBAKE_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
