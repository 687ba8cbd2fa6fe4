// The lane groups' loads in AVX-512 and AVX operations (contact_lanes.hpp, transposeIntoLanes): eight (four)
// contacts' runs of consecutive doubles become the same fields across eight (four) lanes by 8 × 8 (4 × 4)
// transposes, sixteen loads and stores and twenty-four shuffles for what lane-by-lane copies do in a
// hundred and twenty-eight scalar moves (eight loads and stores and eight shuffles for thirty-two). Copies
// only: the lanes hold the bits loadPoint would give them (tested against it). Compiled under target
// pragmas and picked at run time where the CPU has the instructions, as the sweeps are
// (lane_sweeps_wide.cpp); nothing with Eigen is compiled under the pragmas.
#include "contact_lanes.hpp"

#ifdef RIGID_BODY_WIDE_CONTACT_LANES

#include <immintrin.h>

#include <algorithm>
#include <cstddef>

#pragma GCC push_options
#pragma GCC target("avx512f")

namespace rigid_body {
namespace contact {

namespace {

// rows[l] holds elements 0..7 of lane l; afterwards rows[f] holds element f of every lane (lane l at l).
// unpacklo/hi pair the even and odd elements of two rows in each 128-bit part; two rounds of 128-bit
// shuffles then gather the parts (imm 0x44 / 0xEE: parts 0, 1 / 2, 3 of each input; 0x88 / 0xDD: parts
// 0, 2 / 1, 3).
inline void transpose8(__m512d rows[8]) {
  __m512d t[8];
  for (int i = 0; i < 4; ++i) {
    t[2 * i] = _mm512_unpacklo_pd(rows[2 * i], rows[2 * i + 1]);      // elements 0, 2, 4, 6 of two lanes
    t[2 * i + 1] = _mm512_unpackhi_pd(rows[2 * i], rows[2 * i + 1]);  // elements 1, 3, 5, 7
  }
  for (int odd = 0; odd < 2; ++odd) {
    const __m512d low01 = _mm512_shuffle_f64x2(t[odd], t[2 + odd], 0x44);   // elements 0|1, 2|3: lanes 0–3
    const __m512d high01 = _mm512_shuffle_f64x2(t[odd], t[2 + odd], 0xEE);  // elements 4|5, 6|7: lanes 0–3
    const __m512d low23 = _mm512_shuffle_f64x2(t[4 + odd], t[6 + odd], 0x44);
    const __m512d high23 = _mm512_shuffle_f64x2(t[4 + odd], t[6 + odd], 0xEE);
    rows[odd] = _mm512_shuffle_f64x2(low01, low23, 0x88);
    rows[2 + odd] = _mm512_shuffle_f64x2(low01, low23, 0xDD);
    rows[4 + odd] = _mm512_shuffle_f64x2(high01, high23, 0x88);
    rows[6 + odd] = _mm512_shuffle_f64x2(high01, high23, 0xDD);
  }
}

}  // namespace

void transposeIntoLanes(EightLanes* to, const double* const* from, std::size_t count) {
  // Eight fields at a time; the last eight end at `count` (overlapping the ones before: the same values).
  for (std::size_t start = 0; start < count; start += 8) {
    const std::size_t first = std::min(start, count - 8);
    __m512d rows[8];
    for (int l = 0; l < 8; ++l) rows[l] = _mm512_loadu_pd(from[l] + first);
    transpose8(rows);
    for (int f = 0; f < 8; ++f) _mm512_store_pd(reinterpret_cast<double*>(to + first + f), rows[f]);
  }
}

}  // namespace contact
}  // namespace rigid_body

#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx")

namespace rigid_body {
namespace contact {

void transposeIntoLanes(Lanes* to, const double* const* from, std::size_t count) {
  // Four fields at a time; the last four end at `count` (overlapping the ones before: the same values).
  for (std::size_t start = 0; start < count; start += 4) {
    const std::size_t first = std::min(start, count - 4);
    __m256d rows[4];
    for (int l = 0; l < 4; ++l) rows[l] = _mm256_loadu_pd(from[l] + first);
    // unpacklo/hi pair the even and odd elements of two rows in each 128-bit half; permute2f128 then joins
    // the halves (0x20: the low halves of both, 0x31: the high ones).
    const __m256d even01 = _mm256_unpacklo_pd(rows[0], rows[1]), odd01 = _mm256_unpackhi_pd(rows[0], rows[1]);
    const __m256d even23 = _mm256_unpacklo_pd(rows[2], rows[3]), odd23 = _mm256_unpackhi_pd(rows[2], rows[3]);
    double* out = reinterpret_cast<double*>(to + first);
    _mm256_store_pd(out, _mm256_permute2f128_pd(even01, even23, 0x20));
    _mm256_store_pd(out + 4, _mm256_permute2f128_pd(odd01, odd23, 0x20));
    _mm256_store_pd(out + 8, _mm256_permute2f128_pd(even01, even23, 0x31));
    _mm256_store_pd(out + 12, _mm256_permute2f128_pd(odd01, odd23, 0x31));
  }
}

}  // namespace contact
}  // namespace rigid_body

#pragma GCC pop_options

#endif  // RIGID_BODY_WIDE_CONTACT_LANES
