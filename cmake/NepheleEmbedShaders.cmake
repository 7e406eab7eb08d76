# Embeds glsl/ into the binary at build time (render/gl/shader_sources.cpp); #include resolved here,
# and the binding points of src/render/gl/bindings.h injected as #defines into every stage.
file(GLOB_RECURSE NEPHELE_GLSL_FILES CONFIGURE_DEPENDS
     ${PROJECT_SOURCE_DIR}/glsl/*.glsl ${PROJECT_SOURCE_DIR}/glsl/*.comp
     ${PROJECT_SOURCE_DIR}/glsl/*.vert ${PROJECT_SOURCE_DIR}/glsl/*.frag ${PROJECT_SOURCE_DIR}/glsl/*.geom)
set(NEPHELE_GLSL_RESOLVED_DIR ${CMAKE_BINARY_DIR}/glsl_resolved)
set(NEPHELE_GLSL_BINDINGS_H ${PROJECT_SOURCE_DIR}/src/render/gl/bindings.h)
set(NEPHELE_SHADER_SOURCES_CPP ${CMAKE_BINARY_DIR}/generated/render/gl/shader_sources.cpp)
add_custom_command(
  OUTPUT ${NEPHELE_SHADER_SOURCES_CPP}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/generated/render/gl
  COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/cmake/embed_glsl.py
          ${PROJECT_SOURCE_DIR}/glsl ${NEPHELE_SHADER_SOURCES_CPP} ${NEPHELE_GLSL_RESOLVED_DIR}
          ${NEPHELE_GLSL_BINDINGS_H} ${NEPHELE_GLSL_FILES}
  DEPENDS ${PROJECT_SOURCE_DIR}/cmake/embed_glsl.py ${NEPHELE_GLSL_BINDINGS_H} ${NEPHELE_GLSL_FILES}
  COMMENT "Embedding GLSL sources")
