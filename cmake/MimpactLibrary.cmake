# mimpact_add_library(<target> <export name> <sources...>): a layer of the library, exported
# and installed as mimpact::<export name>, with its public headers in include/ of its folder.
# Everything a layer includes from elsewhere privately (Boost's headers, internal headers of
# another layer) is linked with $<BUILD_INTERFACE:...> so that the installed package does
# not ask for it.
function(mimpact_add_library target export_name)
  add_library(${target} ${ARGN})
  add_library(mimpact::${export_name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${export_name}
                                             POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${target}
    PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
           $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:mimpact_warnings>)
  install(TARGETS ${target} EXPORT mimpactTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
