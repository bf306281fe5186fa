// railvib/common: forced inlining of the soil kernels' inner bodies.
//
// The kernels (stencil, element, PML rows) expand their inner loops through always_inline templates so
// that each instruction-set variant is one flat, vectorised loop. Under AddressSanitizer every access of
// that flat code is instrumented and one file took more than ten minutes to compile; the sanitizer build
// therefore lets the compiler choose what to inline. The code and its address arithmetic are the same,
// only its speed differs, which a sanitizer build does not measure.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define RAILVIB_FORCE_INLINE inline
#else
#define RAILVIB_FORCE_INLINE inline __attribute__((always_inline))
#endif
