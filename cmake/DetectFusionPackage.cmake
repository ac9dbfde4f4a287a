# The installed DetectFusion package: the export set the libraries of common/ joined
# (df_export_library), DetectFusionConfig.cmake (finds the dependencies, then the targets) and
# its version file, under lib/cmake/DetectFusion. docs/library.md says how to use it.
include(CMakePackageConfigHelpers)
set(df_package_dir ${CMAKE_INSTALL_LIBDIR}/cmake/DetectFusion)

# What the config finds again for the users: the libraries' public and (static libraries)
# link-only dependencies.
set(DF_PACKAGE_OPENCV_COMPONENTS "core imgproc imgcodecs")
if(TARGET df_detect)
  string(APPEND DF_PACKAGE_OPENCV_COMPONENTS " dnn")
endif()
get_property(df_zstd GLOBAL PROPERTY DF_ZSTD_TARGET)  # common/mcap
if(df_zstd MATCHES "^zstd::")
  set(DF_PACKAGE_FIND_ZSTD "find_dependency(zstd CONFIG)")
else()
  set(DF_PACKAGE_FIND_ZSTD "# zstd: linked by path (${df_zstd})")
endif()

install(EXPORT DetectFusionTargets NAMESPACE DetectFusion:: DESTINATION ${df_package_dir})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/DetectFusionConfig.cmake.in
  ${CMAKE_BINARY_DIR}/package/DetectFusionConfig.cmake INSTALL_DESTINATION ${df_package_dir})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/package/DetectFusionConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/package/DetectFusionConfig.cmake
  ${CMAKE_BINARY_DIR}/package/DetectFusionConfigVersion.cmake DESTINATION ${df_package_dir})
