#pragma once
// A small valid fabric record written to a scratch folder, for tests that break one thing
// at a time. Line numbers of the files are fixed and used by the tests.

#include <string>

#include "tests/test_support.hpp"

namespace yarnfit::testing {

// fabric.yaml of the base record; the comments give the line numbers tests rely on.
inline const std::string k_base_fabric_yaml =
    "id: T1\n"                                               // 1
    "family: test-family\n"                                  // 2
    "description: base record for validation tests\n"        // 3
    "areal_density_gsm: 200\n"                               // 4
    "yarns:\n"                                               // 5
    "  - material: polyester\n"                              // 6
    "    denier: 72\n"                                       // 7
    "    filaments: 75\n"                                    // 8
    "    mass_fraction: 0.9\n"                               // 9
    "    stiffness_N: 85.0\n"                                // 10
    "  - material: spandex\n"                                // 11
    "    denier: 20\n"                                       // 12
    "    mass_fraction: 0.1\n"                               // 13
    "swatch: {length_mm: 100, width_mm: 60}\n"               // 14
    "stretch_tests:\n"                                       // 15
    "  weft: {file: stretch_weft.csv}\n"                     // 16
    "  warp:\n"                                              // 17
    "    file: stretch_warp.csv\n"                           // 18
    "    swatch: {length_mm: 69.2, width_mm: 66.6}\n"        // 19
    "    gauge: {length_mm: 59.4, width_mm: 31.5}\n"         // 20
    "bending_tests:\n"                                       // 21
    "  weft: {file: bend_weft.csv}\n";                       // 22

inline const std::string k_base_stretch_csv =
    "stretch,force_N,compression\n"  // 1
    "0.0,0.0,0.0\n"                  // 2
    "0.1,0.5,0.02\n"                 // 3
    "0.2,1.2,0.05\n"                 // 4
    "0.3,2.4,0.08\n";                // 5

inline const std::string k_base_bend_csv =
    "clamp_distance_mm,aspect_ratio\n"  // 1
    "3,1.35\n"                          // 2
    "13,1.25\n"                         // 3
    "23,1.16\n"                         // 4
    "34,1.08\n";                        // 5

// Writes the base record into `folder`.
inline void write_base_fabric(const fs::path& folder, const std::string& id = "T1") {
  std::string yaml = k_base_fabric_yaml;
  yaml.replace(yaml.find("id: T1"), 6, "id: " + id);
  write_file(folder / "fabric.yaml", yaml);
  write_file(folder / "stretch_weft.csv", k_base_stretch_csv);
  write_file(folder / "stretch_warp.csv", k_base_stretch_csv);
  write_file(folder / "bend_weft.csv", k_base_bend_csv);
}

// Replaces the first occurrence of `from` in `file` by `to`; fails the test if absent.
inline void replace_in_file(const fs::path& file, const std::string& from, const std::string& to) {
  std::string text = read_file(file);
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos) << "'" << from << "' not in " << file;
  text.replace(at, from.size(), to);
  write_file(file, text);
}

// Gives the base record in `folder` a pattern line (a YAML flow map such as
// "{knit: seed, stitch_length_mm: 15.67, yarn_radius_mm: 1.2}") on line 14, before the swatch.
inline void add_pattern_line(const fs::path& folder, const std::string& pattern_flow) {
  replace_in_file(folder / "fabric.yaml", "swatch: {length_mm: 100", "pattern: " + pattern_flow + "\nswatch: {length_mm: 100");
}

}  // namespace yarnfit::testing
