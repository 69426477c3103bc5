/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Linked into the GL-using programs of the AddressSanitizer build only (CAGEKIT_SANITIZE).
 *
 * eglTerminate makes Mesa dlclose its DRI driver (llvmpipe: swrast_dri.so and the LLVM it
 * loads). Allocations the driver still holds in its globals then point from unmapped memory, and
 * LeakSanitizer reports them as direct leaks from "<unknown module>" (128 bytes, realloc, Mesa
 * 22.3.6-1+deb12u2), which no suppression can name. Opening the same driver once more with
 * RTLD_NODELETE before main keeps it mapped, so LeakSanitizer sees its globals and reports
 * only real leaks (none remain). Without the driver file (another GL stack) this does nothing. */
#include <dlfcn.h>

__attribute__((constructor)) static void cagekit_keep_gl_driver_resident(void) {
  (void)dlopen(CAGEKIT_GL_DRIVER_PATH, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
}
