# Generates the GL function-pointer loader (render/gl/gl_functions.{h,cpp}) from glcorearb.h.
find_file(NEPHELE_GLCOREARB_H GL/glcorearb.h REQUIRED)
set(NEPHELE_GL_LOADER_DIR ${CMAKE_BINARY_DIR}/generated/render/gl)
add_custom_command(
  OUTPUT ${NEPHELE_GL_LOADER_DIR}/gl_functions.h ${NEPHELE_GL_LOADER_DIR}/gl_functions.cpp
  COMMAND ${CMAKE_COMMAND} -E make_directory ${NEPHELE_GL_LOADER_DIR}
  COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/cmake/gen_gl_loader.py
          ${NEPHELE_GLCOREARB_H} ${NEPHELE_GL_LOADER_DIR}/gl_functions.h ${NEPHELE_GL_LOADER_DIR}/gl_functions.cpp
  DEPENDS ${PROJECT_SOURCE_DIR}/cmake/gen_gl_loader.py ${NEPHELE_GLCOREARB_H}
  COMMENT "Generating OpenGL 4.6 core loader from glcorearb.h")
