# One place that sets the language standard and warnings for every target of the project.
function(df_target_defaults target)
  target_compile_features(${target} PUBLIC cxx_std_17)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF POSITION_INDEPENDENT_CODE ON)
  get_target_property(type ${target} TYPE)
  if(NOT type STREQUAL "INTERFACE_LIBRARY")
    target_compile_options(${target} PRIVATE
      $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor>
      $<$<COMPILE_LANGUAGE:C>:-Wall -Wextra>)
  endif()
endfunction()

# df_add_gtest(name SOURCES ... LIBS ...): a gtest executable registered with CTest.
function(df_add_gtest name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  df_target_defaults(${name})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  target_include_directories(${name} PRIVATE ${CMAKE_SOURCE_DIR}/tests/support)
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  add_test(NAME ${name} COMMAND ${name})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 120)
  endif()
  if(DF_SANITIZE)
    math(EXPR ARG_TIMEOUT "${ARG_TIMEOUT} * 5")  # sanitized code runs 2-5x slower
  endif()
  set_tests_properties(${name} PROPERTIES TIMEOUT ${ARG_TIMEOUT})
  if(ARG_LABELS)
    set_tests_properties(${name} PROPERTIES LABELS "${ARG_LABELS}")
  endif()
endfunction()

# Sanitizers for every target: -DDF_SANITIZE=address,undefined (any -fsanitize= list; empty =
# none). Findings abort the process (no recovery), so a test with a finding fails.
set(DF_SANITIZE "" CACHE STRING "sanitizers for every target, e.g. address,undefined")
if(DF_SANITIZE)
  add_compile_options(-fsanitize=${DF_SANITIZE} -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${DF_SANITIZE})
  # The sanitizer runtimes are linked statically into each executable (the compiler's default).
  # Not -shared-libasan: with -fsanitize=fuzzer clang puts libstdc++ ahead of the shared ASan
  # runtime in the executable's library list, and the fuzz targets then abort at start with "ASan
  # runtime does not come first in initial library list". Shared libraries are left with the ASan
  # symbols undefined, resolved from the executable that loads them (common/io/openni).
endif()

# libFuzzer targets (fuzz/): with clang by default. Every library is built with coverage
# instrumentation for the fuzzer (-fsanitize=fuzzer-no-link); the fuzz executables link libFuzzer.
if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  set(df_fuzz_default ON)
else()
  set(df_fuzz_default OFF)
endif()
option(DF_FUZZ "Build the libFuzzer targets of fuzz/ (needs clang)" ${df_fuzz_default})
if(DF_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "DF_FUZZ=ON needs clang (libFuzzer): -DCMAKE_CXX_COMPILER=clang++ "
                        "-DCMAKE_C_COMPILER=clang")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

# df_export_libraries(df_x=name ...): installs DDS-free libraries into the export set of the
# DetectFusion package (lib/, headers under include/detectfusion/), so that a project doing
# find_package(DetectFusion) links df_x as DetectFusion::<name> (docs/library.md, the table of
# names). Entries whose target this build lacks (df_detect with DF_WITH_DETECT=OFF) are skipped.
# The set is closed over what the libraries link: a project library they link and the list does
# not name (a part added later) is installed too, as DetectFusion::<its name without "df_">;
# one of the DDS layer stops the configuration. cmake/DetectFusionPackage.cmake installs the
# export set and the package config.
include(GNUInstallDirs)
set(DF_INSTALL_INCLUDEDIR ${CMAKE_INSTALL_INCLUDEDIR}/detectfusion)
function(df_export_libraries)
  set(pending ${ARGN})
  set(exported "")
  set(names "")
  while(pending)
    list(POP_FRONT pending entry)
    string(REPLACE "=" ";" entry "${entry}")
    list(GET entry 0 target)
    list(GET entry 1 name)
    if(NOT TARGET ${target} OR target IN_LIST exported)
      continue()
    endif()
    if(target MATCHES "^df_(dds|service|msgs|msgs_c|io_openni)$" OR name IN_LIST names)
      message(FATAL_ERROR "the installed libraries would include ${target} as DetectFusion::${name}"
                          " (the DDS layer, or a name taken): see common/CMakeLists.txt")
    endif()
    set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
    install(TARGETS ${target} EXPORT DetectFusionTargets
      ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
      LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
      INCLUDES DESTINATION ${DF_INSTALL_INCLUDEDIR})
    list(APPEND exported ${target})
    list(APPEND names ${name})
    # A static library's private dependencies are there too, as $<LINK_ONLY:...>.
    get_target_property(links ${target} INTERFACE_LINK_LIBRARIES)
    foreach(link IN LISTS links)
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" link "${link}")
      if(link MATCHES "^df_(.*)$" AND TARGET ${link} AND NOT link IN_LIST exported)
        list(APPEND pending "${link}=${CMAKE_MATCH_1}")
      endif()
    endforeach()
  endwhile()
endfunction()
