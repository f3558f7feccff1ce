// "Did you mean": the registered name nearest to a mistyped one, by edit distance (insertions,
// deletions, substitutions and swaps of neighbours, each 1), for the command line's unknown
// options and subcommands (CLI11 names what it did not expect but suggests nothing).
#pragma once
#include <string>
#include <vector>

namespace rayes {

// Optimal-string-alignment distance between a and b.
int editDistance(const std::string& a, const std::string& b);

// The name of `names` nearest to `typed` when it is near enough to be a typo: at most 1 edit for
// names of up to 4 characters, 2 up to 8, 3 beyond (leading dashes not counted); ties go to the
// earlier name. "" when none is.
std::string closestName(const std::string& typed, const std::vector<std::string>& names);

}  // namespace rayes
