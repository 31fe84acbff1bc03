#pragma once
// The units a record's files are written in, to SI.

namespace yarnfit::db::units {

inline constexpr double k_mm = 1e-3;   // mm → m
inline constexpr double k_gsm = 1e-3;  // g/m² → kg/m²

}  // namespace yarnfit::db::units
