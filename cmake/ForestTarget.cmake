# Warning and sanitizer flags shared by every target of the project.
function(forest_target_options target)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion>
    $<$<BOOL:${FOREST_WERROR}>:-Werror>
    # GCC 12 reports false -Wrestrict positives inside std::string (GCC bug 105329).
    $<$<AND:$<CXX_COMPILER_ID:GNU>,$<VERSION_LESS:$<CXX_COMPILER_VERSION>,13>>:-Wno-restrict>)
  if(FOREST_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
                                             -fno-sanitize-recover=undefined)
    # PUBLIC: whatever links a sanitized library (tests, the installed package's users) needs the runtime.
    target_link_options(${target} PUBLIC -fsanitize=address,undefined)
  endif()
endfunction()

# One module = one folder = one static library forest_<name> (alias forest::<name>),
# public headers under <folder>/include/forest/<name>/.
function(forest_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(forest_${name} STATIC ${ARG_SOURCES})
  add_library(forest::${name} ALIAS forest_${name})
  set_target_properties(forest_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(forest_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(forest_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  forest_target_options(forest_${name})
  install(TARGETS forest_${name} EXPORT forestTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
