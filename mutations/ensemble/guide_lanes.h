#pragma once
// Two guides at a time in double precision (one SSE2 register on x86-64's baseline, written
// with GCC's vector extensions so that it compiles anywhere): what the similarity rows and
// the weights of EMLT's guided steps are computed with. GCC does not vectorise the plain
// loops for these itself (a reduction to a bool, a conversion between widths), and a row of
// eight guides in scalar code cost as much as the rest of a guided step's arithmetic
// (docs/experiments.md, "Cost per mutation"). Every lane runs exactly the scalar
// operations, so the results are the same.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

namespace emlt::ensemble {

using Double2 = double __attribute__((vector_size(16)));
using Mask2 = int64_t __attribute__((vector_size(16)));

[[gnu::always_inline]] inline Double2 load2(const double* p) {
  Double2 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

[[gnu::always_inline]] inline void store2(double* p, Double2 v) {
  std::memcpy(p, &v, sizeof v);
}

// Whether every entry is >= bound (false where one is NaN).
inline bool all_at_least(std::span<const double> values, double bound) {
  const size_t count = values.size();
  const double* v = values.data();
  Mask2 all = {-1, -1};
  size_t n = 0;
  for (; n + 8 <= count; n += 8)  // eight at a time: the loop's own work was half the cost
    all &= (load2(v + n) >= bound) & (load2(v + n + 2) >= bound) & (load2(v + n + 4) >= bound) &
           (load2(v + n + 6) >= bound);
  for (; n + 2 <= count; n += 2) all &= load2(v + n) >= bound;
  bool result = (all[0] & all[1]) != 0;
  if (n < count) result &= v[n] >= bound;
  return result;
}

}  // namespace emlt::ensemble
