# mimpact_add_library(<target> <export name> <sources...>): a layer of the library, exported
# as mimpact::<export name>, with its public headers in include/ of its folder.
function(mimpact_add_library target export_name)
  add_library(${target} ${ARGN})
  add_library(mimpact::${export_name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${export_name}
                                             POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:mimpact_warnings>)
endfunction()
