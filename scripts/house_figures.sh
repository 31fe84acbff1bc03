#!/usr/bin/env bash
# The figures of issue 53's goal table that can be read off the code (the build times are
# measured by timing scripts/example.sh's build and README command 2 from a fresh clone):
#   scripts/house_figures.sh [--list]
# --list also names the long functions and the CLI's includes of module internals.
set -euo pipefail
cd "$(dirname "$0")/.."
list=${1:-}

# Duplicate pairs (the `duplicates` tool of this workplace), the whole tree and outside tests/.
if command -v duplicates >/dev/null; then
  pairs=$(duplicates --seconds 120 --most 200 | grep '^D[0-9]' || true)
  echo "duplicate pairs, whole tree: $(grep -c . <<<"$pairs" || true)"
  echo "duplicate pairs, outside tests: $(grep -vc 'tests/' <<<"$pairs" || true)"
fi

# The CLI's size, and its files that include a module's internals (anything but a module's
# public face: pipeline/, batch/, service/, exports/, reports/, results/, fabrics_db/, numerics/).
echo "cli lines: $(cat cli/*.cpp cli/*.hpp | wc -l)"
internals='#include "(calibration|shell_fit|yarn_fit|swarm)/'
echo "cli files including module internals: $(grep -lE "$internals" cli/*.cpp cli/*.hpp | wc -l)"
[ "$list" = --list ] && grep -nE "$internals" cli/*.cpp cli/*.hpp | sed 's/^/  /'

# Functions over 80 lines where the issue counts them (universal-ctags gives each its end line).
long=$(ctags -R --languages=C++ --kinds-C++=f --fields=+ne -o - pipeline shell_fit yarn_fit results numerics/newton |
  awk -F'\t' '{l=""; e=""; for (i = 4; i <= NF; i++) { if ($i ~ /^line:/) l = substr($i, 6); if ($i ~ /^end:/) e = substr($i, 5) }
               if (l != "" && e != "" && e - l + 1 > 80) printf "  %4d %s:%s %s\n", e - l + 1, $2, l, $1 }' | sort -rn)
echo "functions over 80 lines (pipeline, shell_fit, yarn_fit, results, numerics/newton): $(grep -c . <<<"$long" || true)"
[ "$list" = --list ] && echo "$long"

# Ways to run a fit, stage enums and result types of the pipeline's public headers.
echo "pipeline entry points that run a fit: $(grep -hoE '^[A-Za-z:]+Result run_[a-z_]+\(' pipeline/*.hpp | sort -u | wc -l)"
echo "pipeline stage enums: $(grep -hcE '^enum class Stages?\b' pipeline/*.hpp | paste -sd+ | bc)"
echo "pipeline result types: $(grep -hcE '^struct (Pipeline|Plan|Fit)Result\b' pipeline/*.hpp | paste -sd+ | bc)"

# One error style: the library's throws of bare standard exceptions for what a user can act on,
# and the exception classes it defines (numerics/util/error.hpp's Error is meant to be the one).
libs="fabrics_db shell_fit yarn_fit swarm pipeline batch reports results service exports numerics cli"
echo "library throws of std::invalid_argument or std::runtime_error: $(grep -rhoE 'throw std::(invalid_argument|runtime_error)\(' $libs | wc -l)"
echo "exception classes: $(grep -rhE '^class [A-Za-z0-9_]+ : public std::[a-z_]+' $libs | wc -l)"
