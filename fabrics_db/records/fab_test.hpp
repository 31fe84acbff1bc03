#pragma once
// A test of a Browzwear Fabric Analyzer (FAB; docs/fab.md) as a record keeps it: a strip
// between two clamps, the stationary one on the load cell, the other moved away (stretch S1,
// S2) or towards it (the loop-method bends U1 up, D1 and D2 down), at a clamp distance of
// 2 or 8 cm, in 3–4 cycles of a loading and a relaxation branch each. Every sample is kept
// as the load cell read it, in SI units; the zero offset, where the test lets one be
// estimated, is stated beside the samples rather than taken off them.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace yarnfit::db {

enum class FabTestKind { stretch, up_bend, down_bend };
enum class FabBranch { loading, relaxation };

std::string_view to_string(FabTestKind kind);
std::string_view to_string(FabBranch branch);
std::optional<FabBranch> parse_fab_branch(std::string_view name);

// The protocol's five tests per grain: name, kind and nominal clamp distance [m].
struct FabTestName {
  const char* name;
  FabTestKind kind;
  double nominal_distance;
};
inline constexpr FabTestName k_fab_tests[] = {{"S1", FabTestKind::stretch, 0.02},
                                              {"S2", FabTestKind::stretch, 0.08},
                                              {"U1", FabTestKind::up_bend, 0.02},
                                              {"D1", FabTestKind::down_bend, 0.02},
                                              {"D2", FabTestKind::down_bend, 0.08}};
const FabTestName* find_fab_test(std::string_view name);

struct FabBranchCurve {
  int cycle = 0;  // 1-based
  FabBranch branch = FabBranch::loading;
  std::vector<double> clamp_distance;  // [m], as the motor read it
  std::vector<double> raw_force;       // [N], the load cell's reading, zero not removed
  std::vector<int> source_lines;       // CSV line of each sample (records only)
};

struct FabTest {
  std::string name;  // S1, S2, U1, D1, D2
  std::filesystem::path file;  // the record's CSV of it (empty when read from a physics file)
  FabTestKind kind = FabTestKind::stretch;
  double clamp_distance = 0.0;  // the file's `length`: the free length where the strip is taut [m]
  double strip_width = 0.0;     // [m]
  std::optional<double> zero_offset;  // [N] the load cell's reading at no load, if estimated
  int zero_offset_samples = 0;        // samples the estimate took
  std::optional<int> sampling_hz;
  std::optional<long long> test_version;
  std::optional<long long> time;  // seconds since 1970-01-01 UTC
  std::vector<FabBranchCurve> branches;  // in the file's order: cycle 1 loading, relaxation, …
};

// A record's `fab_tests.source`: the physics file as the FAB wrote it, and the device.
struct FabSource {
  std::filesystem::path file;  // inside the record's folder; empty when not kept
  std::optional<long long> serial, hardware_version, build;
};

}  // namespace yarnfit::db
