// The command line's one progress display (cli/progress_display.hpp), driven by events with
// their own clock: the line's fields, the time left (about / at most, per stage), a new line
// per task, and silence when disabled.
#include <gtest/gtest.h>

#include <limits>
#include <sstream>
#include <string>

#include "cli/option_names.hpp"
#include "cli/request_options.hpp"
#include "cli/progress_display.hpp"

namespace yarnfit::cli {
namespace {

numerics::Progress event(const std::string& stage, int step, int steps, double seconds, bool budget = false) {
  numerics::Progress p;
  p.stage = stage;
  p.step = step;
  p.steps = steps;
  p.budget = budget;
  p.seconds = seconds;
  p.best = 0.0123;
  p.best_label = "objective";
  return p;
}

TEST(ProgressDisplay, StageStepBestElapsedAndTimeLeftFromTheStagesPace) {
  std::ostringstream out;
  ProgressDisplay d(out, true);
  // 2 of 10 iterations in 4 s: 2 s each, 16 s left.
  EXPECT_EQ(d.line("yarn fit A2", event("swarm", 1, 10, 2.0)),
            "yarn fit A2: swarm, iteration 1/10, best objective 0.0123, 2.0 s, about 18 s left in this stage");
  EXPECT_EQ(d.line("yarn fit A2", event("swarm", 2, 10, 4.0)),
            "yarn fit A2: swarm, iteration 2/10, best objective 0.0123, 4.0 s, about 16 s left in this stage");
  // A new stage is timed from the previous stage's last event; a budget is an upper bound.
  numerics::Progress local = event("local", 3, 40, 7.0, true);
  local.step_name = "evaluation";
  local.step = 1;
  EXPECT_EQ(d.line("yarn fit A2", local),
            "yarn fit A2: local, evaluation 1/40, best objective 0.0123, 7.0 s, at most 117 s left in this stage");
  // The last step leaves nothing to estimate; unknown steps give no estimate either.
  EXPECT_EQ(d.line("yarn fit A2", event("local", 40, 40, 50.0, true)).find("left"), std::string::npos);
  EXPECT_EQ(d.line("yarn fit A2", event("local", 41, 0, 51.0)).find("left"), std::string::npos);
}

TEST(ProgressDisplay, UnitsDetailsAndStagelessTasks) {
  std::ostringstream out;
  ProgressDisplay d(out, true);
  numerics::Progress shell = event("in-plane (weft, warp) start 1/3", 1, 8, 0.5, true);
  shell.best = 1.234;
  shell.best_label = "rms error";
  shell.best_unit = "%";
  EXPECT_EQ(d.line("shell fit", shell).rfind("shell fit: in-plane (weft, warp) start 1/3, iteration 1/8, best rms error "
                                             "1.234 %, 0.5 s, at most ",
                                             0),
            0u);
  numerics::Progress point;
  point.step_name = "point";
  point.step = 1;
  point.steps = 2;
  point.detail = "s = 0.05";
  point.seconds = 3.0;
  EXPECT_EQ(d.line("yarn curve weft", point), "yarn curve weft: point 1/2, s = 0.05, 3.0 s, about 3 s left");
  numerics::Progress before_any = event("swarm", 0, 10, 0.0);
  before_any.best = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(d.line("yarn fit", before_any).find("best objective -, "), std::string::npos);
}

TEST(ProgressDisplay, RewritesOneLinePerTaskAndEndsIt) {
  std::ostringstream out;
  ProgressDisplay d(out, true);
  d.update("shell fit", event("in-plane", 1, 0, 1.0));
  d.update("shell fit", event("in-plane", 2, 0, 2.0));
  d.update("yarn fit", event("swarm", 1, 0, 1.0));
  d.finish();
  EXPECT_EQ(out.str(),
            "\r\033[Kshell fit: in-plane, iteration 1, best objective 0.0123, 1.0 s"
            "\r\033[Kshell fit: in-plane, iteration 2, best objective 0.0123, 2.0 s\n"
            "\r\033[Kyarn fit: swarm, iteration 1, best objective 0.0123, 1.0 s\n");
}

TEST(ProgressDisplay, SilentWhenDisabled) {
  std::ostringstream out;
  ProgressDisplay d(out, false);
  EXPECT_FALSE(d.callback("shell fit"));  // the libraries then skip building events
  d.update("shell fit", event("in-plane", 1, 8, 1.0));
  d.finish();
  EXPECT_TRUE(out.str().empty());
}

// Each field of a fit request is one option of its group's commands, with the field list's
// help, and a problem naming the field or a setting it sets names that option.
TEST(OptionNames, EveryFitRequestFieldIsTheOptionItsGroupRegisters) {
  pipeline::FitRequest request;
  int fields = 0;
  pipeline::for_each_request_field(request, [&](const pipeline::RequestField& f, auto&) {
    ++fields;
    CLI::App app;
    add_request_options(app, request, f.group);
    const std::string first = first_option_name(f.option);
    const CLI::Option* option = app.get_option_no_throw(first);
    ASSERT_NE(option, nullptr) << f.name;
    EXPECT_EQ(option->get_description(), f.help) << f.name;
    EXPECT_EQ(option_name(f.name), first);
    for (const char* setting : f.settings_names) EXPECT_EQ(option_name(std::string("yarn.") + setting), first);
  });
  EXPECT_GE(fields, 25);
}

TEST(OptionNames, LibraryFieldsShowAsTheOptionsTheUserTyped) {
  EXPECT_EQ(option_name("yarn.swarm_samples"), "--samples");
  EXPECT_EQ(option_name("particles"), "--particles");
  EXPECT_EQ(option_name("shell.mesh"), "--mesh");
  EXPECT_EQ(option_name("yarn.local_min_scale"), "yarn.local_min_scale");  // no option sets it
  db::Problems p;
  p.add("", 0, "yarn.swarm_compression_nodes", "must be 0 or at least 2");
  p.add("", 0, "yarn.local_compression_nodes", "must be 0 or at least 2");  // the same option
  p.add("fabric.yaml", 0, "pattern", "missing");                            // a file's field stays
  EXPECT_EQ(as_options(p).to_string(), "--compression-nodes: must be 0 or at least 2\nfabric.yaml: pattern: missing\n");
}

}  // namespace
}  // namespace yarnfit::cli
