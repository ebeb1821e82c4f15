# GL loader generated at build time with glad 2 (Debian python3-glad), offline and reproducible
# (DESIGN §3). It is loaded at run time through the active backend's getProcAddress.
find_program(GLAD_PYTHON NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH)
if(NOT GLAD_PYTHON)
  find_program(GLAD_PYTHON NAMES python3 REQUIRED)
endif()
execute_process(COMMAND ${GLAD_PYTHON} -c "import glad" RESULT_VARIABLE _glad_missing OUTPUT_QUIET ERROR_QUIET)
if(_glad_missing)
  message(FATAL_ERROR "glad 2 not importable by ${GLAD_PYTHON}: run tools/setup.sh (package python3-glad)")
endif()

set(GLAD_OUT "${CMAKE_CURRENT_BINARY_DIR}/glad")
set(GLAD_EXTENSIONS GL_KHR_debug,GL_ARB_clip_control,GL_EXT_texture_filter_anisotropic)
add_custom_command(
  OUTPUT "${GLAD_OUT}/src/gl.c" "${GLAD_OUT}/include/glad/gl.h" "${GLAD_OUT}/include/KHR/khrplatform.h"
  COMMAND ${GLAD_PYTHON} -m glad --quiet --reproducible --api gl:core=4.5
          --extensions ${GLAD_EXTENSIONS} --out-path "${GLAD_OUT}" c
  COMMENT "Generating the GL 4.5 core loader with glad"
  VERBATIM)
add_library(forest_glad STATIC "${GLAD_OUT}/src/gl.c")
set_target_properties(forest_glad PROPERTIES EXPORT_NAME glad)
target_include_directories(forest_glad PUBLIC
  $<BUILD_INTERFACE:${GLAD_OUT}/include>
  $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/forest/third_party>)
install(TARGETS forest_glad EXPORT forestTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY "${GLAD_OUT}/include/" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/forest/third_party)
