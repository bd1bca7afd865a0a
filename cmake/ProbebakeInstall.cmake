# `cmake --install BUILD --prefix P` installs what a game engine links: the runtime library and the static
# libraries it needs (formats, dynamic, streaming, the embedded shaders), their public headers, the GLSL includes a
# game's own shaders use (probebake/sample_irradiance.glsl and the struct headers), and a CMake package:
#   find_package(probebake CONFIG REQUIRED)
#   target_link_libraries(game PRIVATE probebake::runtime)
#   # GLSL: glslangValidator -I <prefix>/include (variable probebake_GLSL_INCLUDE_DIR)
# tests/consumer builds such a project against an install made by the `consumer` CTest test.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(probebake_install_targets probebake_runtime probebake_formats probebake_dynamic probebake_streaming
    probebake_gpu_types probebake_runtime_shaders)
foreach(target IN LISTS probebake_install_targets)
  target_include_directories(${target} INTERFACE $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
endforeach()
set_target_properties(probebake_runtime PROPERTIES EXPORT_NAME runtime)
set_target_properties(probebake_formats PROPERTIES EXPORT_NAME formats)
set_target_properties(probebake_dynamic PROPERTIES EXPORT_NAME dynamic)
set_target_properties(probebake_streaming PROPERTIES EXPORT_NAME streaming)
set_target_properties(probebake_gpu_types PROPERTIES EXPORT_NAME gpu_types)
set_target_properties(probebake_runtime_shaders PROPERTIES EXPORT_NAME runtime_shaders)

install(TARGETS ${probebake_install_targets} EXPORT probebakeTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# Headers: the public ones of each library, and the shared C++/GLSL ones (gpu_types.h, bindings.h, the
# .glsl includes). Private headers (src/) stay out.
install(DIRECTORY runtime/include/ formats/include/ dynamic/include/ runtime/streaming/policy/include/ shaders/include/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT probebakeTargets NAMESPACE probebake:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/probebake)

set(probebake_config_dir "${CMAKE_CURRENT_BINARY_DIR}/package")
configure_package_config_file(cmake/probebakeConfig.cmake.in "${probebake_config_dir}/probebakeConfig.cmake"
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/probebake
                              PATH_VARS CMAKE_INSTALL_INCLUDEDIR)
write_basic_package_version_file("${probebake_config_dir}/probebakeConfigVersion.cmake"
                                 COMPATIBILITY SameMinorVersion)
install(FILES "${probebake_config_dir}/probebakeConfig.cmake" "${probebake_config_dir}/probebakeConfigVersion.cmake"
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/probebake)
