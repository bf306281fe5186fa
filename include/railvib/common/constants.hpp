// railvib/common: mathematical constants, defined once (C++17 has no std::numbers).
#pragma once

namespace railvib {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kTwoPi = 2.0 * kPi;

}  // namespace railvib
