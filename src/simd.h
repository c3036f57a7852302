/* AVX2 helpers shared by the models' vector paths (model_thin.c,
 * model_exact.c): four doubles a vector, one point a lane, no fused
 * multiply-add (target "avx2" only), so each lane computes what the
 * scalar code does, bit for bit.  Include only where the AVX2 path is
 * compiled (x86-64, GCC or Clang). */
#ifndef LF_SIMD_H
#define LF_SIMD_H

#include <immintrin.h>

#include "internal.h"

#define LF_AVX2 static inline __attribute__((target("avx2"), always_inline))

typedef __m256d v4;

LF_AVX2 v4
bc(double x)
{
    return _mm256_set1_pd(x);
}

/* lf_capped lane by lane: vminpd is x < BIG ? x : BIG and vmaxpd
 * x > -BIG ? x : -BIG, lf_capped's two selections (a NaN becomes BIG) */
LF_AVX2 v4
vcapped(v4 x)
{
    return _mm256_max_pd(_mm256_min_pd(x, bc(LF_BIG)), bc(-LF_BIG));
}

/* Four consecutive records of six numbers at p (four lf_evals, or the
 * exact model's root records) from their six fields across the lanes:
 * f[j] holds field j of the four points. */
LF_AVX2 void
st_six(double *p, const v4 f[6])
{
    int j;

    for (j = 0; j < 6; j += 2) {
        const v4 lo = _mm256_unpacklo_pd(f[j], f[j + 1]), hi = _mm256_unpackhi_pd(f[j], f[j + 1]);
        _mm_storeu_pd(p + j, _mm256_castpd256_pd128(lo));
        _mm_storeu_pd(p + 6 + j, _mm256_castpd256_pd128(hi));
        _mm_storeu_pd(p + 12 + j, _mm256_extractf128_pd(lo, 1));
        _mm_storeu_pd(p + 18 + j, _mm256_extractf128_pd(hi, 1));
    }
}

#endif
