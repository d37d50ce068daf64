# sscs_add_plugin(NAME SOURCE...): a plugin shared object NAME.so in ${CMAKE_BINARY_DIR}/plugins,
# built against sscs/plugin.h (SSCS_INCLUDE_DIR), with only its two entry points exported.
# Load it with `sscs ... --plugins ${CMAKE_BINARY_DIR}/plugins`.
function(sscs_add_plugin name)
  add_library(${name} MODULE ${ARGN})
  target_include_directories(${name} PRIVATE ${SSCS_INCLUDE_DIR})
  target_compile_features(${name} PRIVATE cxx_std_17)
  set_target_properties(${name} PROPERTIES PREFIX "" LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/plugins
                                           CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
endfunction()
