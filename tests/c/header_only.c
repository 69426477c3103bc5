/* Compiles the public headers alone (as C99 and as C++): the main header, then the opt-in GL
 * binding with its experimental part. */
#include <cagekit/cagekit.h>
#define CAGEKIT_ENABLE_EXPERIMENTAL
#include <cagekit/cagekit_gl.h>
int main(void) {
  cagekit_gl_deformer_options options = CAGEKIT_GL_DEFORMER_OPTIONS_INIT;
  return cagekit_version() == 0 || options.optimize_vertex_cache != CAGEKIT_TRUE;
}
