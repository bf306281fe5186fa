// Sampled cases in the sanitizer run. Under AddressSanitizer and UBSan the numerical kernels run 7 to
// 30 times slower than in the release build (measured at -O1; up to 1.6 x that at -Og, the level now),
// so `./railvib sanitize` sets RAILVIB_TEST_SAMPLE_STRIDE=n: a test that sweeps many like cases
// (frequencies of a receptance, values of a config fuzz) takes every n-th of them there, the first and
// the last always, and all of them in the regular build; a long time loop of like steps runs 1/n of its
// steps there. The code paths are the same; only how many times they run differs.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <vector>

namespace railvib::test {

// n of RAILVIB_TEST_SAMPLE_STRIDE; 1 (every case) when unset or not a positive number.
inline size_t sampleStride() {
  const char* s = std::getenv("RAILVIB_TEST_SAMPLE_STRIDE");
  if (s == nullptr) return 1;
  char* end = nullptr;
  const long n = std::strtol(s, &end, 10);
  return (end != s && *end == '\0' && n >= 1) ? static_cast<size_t>(n) : 1;
}

// Every sampleStride()-th of cases, with the first and the last.
template <class T>
std::vector<T> sampled(const std::vector<T>& cases) {
  const size_t stride = sampleStride();
  if (stride == 1 || cases.size() <= 2) return cases;
  std::vector<T> out;
  for (size_t i = 0; i < cases.size(); i += stride) out.push_back(cases[i]);
  if ((cases.size() - 1) % stride != 0) out.push_back(cases.back());
  return out;
}

// The steps of a time loop whose every step runs the same code (an energy balance held step by step):
// all `steps` in the regular build, every n-th as many (at least `minimum`) in the sanitizer run.
inline int sampledSteps(int steps, int minimum = 1) {
  return std::min(steps, std::max(minimum, steps / static_cast<int>(sampleStride())));
}

}  // namespace railvib::test
