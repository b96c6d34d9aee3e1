# `cmake --install BUILD --prefix P`: the embeddable core only (DESIGN.md: acuity + lod are what an
# engine takes), never the GL, device or app parts, which need this checkout's data and packages.
#   P/include/hmdlod/{base,acuity,lod}/*.h   the public headers, laid out as in the source tree so
#                                            their own #include "acuity/acuity.h" lines resolve with
#                                            -IP/include/hmdlod (the .pc file's Cflags)
#   P/lib/libhmdlod_{lod,acuity,base}.a      the static libraries, renamed with the project prefix
#   P/lib/pkgconfig/hmdlod.pc                pkg-config file, relocatable (prefix from its own path)
include(GNUInstallDirs)

set_target_properties(hl_base PROPERTIES OUTPUT_NAME hmdlod_base)
set_target_properties(acuity PROPERTIES OUTPUT_NAME hmdlod_acuity)
set_target_properties(lod PROPERTIES OUTPUT_NAME hmdlod_lod)

install(TARGETS lod acuity hl_base ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
foreach(header IN ITEMS base/base.h acuity/acuity.h acuity/gaze.h acuity/saccade.h acuity/csf.h lod/lod.h)
  get_filename_component(dir ${header} DIRECTORY)
  install(FILES ${CMAKE_SOURCE_DIR}/${header} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/hmdlod/${dir})
endforeach()

# The core's interface version: bumped when lod.h or acuity.h change incompatibly.
set(HMDLOD_CORE_VERSION 0.2) # 0.2: lod_problem.keep, lod_cost_rls refitted (issue 30); acuity/csf.h
configure_file(${CMAKE_CURRENT_LIST_DIR}/hmdlod.pc.in ${CMAKE_BINARY_DIR}/hmdlod.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/hmdlod.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
