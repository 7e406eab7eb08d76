# nephele_warnings(<target>): the project's warning set; -Werror when NEPHELE_WERROR is ON.
function(nephele_warnings target)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANG_AND_ID:CXX,GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
        -Wold-style-cast -Wcast-align -Woverloaded-virtual -Wconversion -Wno-sign-conversion
        -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough>
    # clang's -Wdouble-promotion also flags every (lossless) float -> double initialisation, which
    # gcc's does not; the gcc build keeps the warning for arithmetic promoted by accident.
    $<$<COMPILE_LANG_AND_ID:CXX,Clang>:-Wno-double-promotion>
    $<$<COMPILE_LANG_AND_ID:C,GNU,Clang>:-Wall -Wextra -Wpedantic>
    $<$<BOOL:${NEPHELE_WERROR}>:-Werror>)
endfunction()

# nephele_module(<name> SOURCES ... DEPS ...): one library target per module, nephele::<name>.
# Modules are internal static libraries and are not installed: the installed interface is the
# plugin C API alone (libnephele.so.0 + include/nephele/nephele.h, src/api; issue 17).
function(nephele_module name)
  cmake_parse_arguments(M "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(nephele_${name} ${M_SOURCES})
  add_library(nephele::${name} ALIAS nephele_${name})
  set_target_properties(nephele_${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME nephele_${name})
  target_include_directories(nephele_${name} PUBLIC ${PROJECT_SOURCE_DIR}/src)
  target_link_libraries(nephele_${name} PUBLIC ${M_PUBLIC_DEPS} PRIVATE ${M_PRIVATE_DEPS})
  target_compile_features(nephele_${name} PUBLIC cxx_std_20)
  nephele_warnings(nephele_${name})
endfunction()

# nephele_vectorise(<target>): GCC's loop vectoriser with the cost model of -O3 (-O2 uses the
# "very cheap" one, which vectorises no loop whose trip count is unknown: the conversion's scans
# over whole model fields stayed scalar; issue 19, convert speed). No change to floating-point
# results: GCC vectorises no floating-point reduction without -ffast-math. Clang vectorises at -O2.
function(nephele_vectorise target)
  target_compile_options(${target} PRIVATE $<$<COMPILE_LANG_AND_ID:CXX,GNU>:-fvect-cost-model=dynamic>)
endfunction()
