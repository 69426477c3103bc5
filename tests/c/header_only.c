/* Compiles the public header alone (as C99 and as C++). */
#include <cagekit/cagekit.h>
int main(void) { return cagekit_version() == 0; }
