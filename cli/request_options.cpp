#include "cli/request_options.hpp"

#include <type_traits>

namespace yarnfit::cli {

using pipeline::is_list;
using pipeline::is_optional;

void add_request_options(CLI::App& cmd, pipeline::FitRequest& request, pipeline::RequestGroup group) {
  // Values are checked by the library (pipeline::pipeline_options, YarnFitSettings::problems and
  // the options of the shell stage), so that one run names every invalid option, not only the
  // first.
  pipeline::for_each_request_field(request, [&](const pipeline::RequestField& f, auto& member) {
    if (f.group != group) return;
    using T = std::decay_t<decltype(member)>;
    if constexpr (std::is_same_v<T, bool>) {
      cmd.add_flag(f.option, member, f.help);
    } else {
      CLI::Option* option = cmd.add_option(f.option, member, f.help);
      if constexpr (is_list<T>) option->delimiter(',');
      // An optional size states its default in its help (the budget's); an empty list has none.
      bool shows_default = !is_optional<T>;
      if constexpr (is_list<T>) shows_default = !member.empty();
      if (shows_default) option->capture_default_str();
    }
  });
}

std::string first_option_name(const char* names) {
  const std::string all = names;
  return all.substr(0, all.find(','));
}

}  // namespace yarnfit::cli
