#include "app/closest_name.h"
#include <algorithm>

namespace rayes {

int editDistance(const std::string& a, const std::string& b) {
  const size_t n = a.size(), m = b.size();
  std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1, 0));
  for (size_t i = 0; i <= n; ++i) d[i][0] = int(i);
  for (size_t j = 0; j <= m; ++j) d[0][j] = int(j);
  for (size_t i = 1; i <= n; ++i)
    for (size_t j = 1; j <= m; ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1])});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

std::string closestName(const std::string& typed, const std::vector<std::string>& names) {
  const size_t letters = typed.size() - std::min(typed.find_first_not_of('-'), typed.size());
  const int allowed = letters <= 4 ? 1 : letters <= 8 ? 2 : 3;
  std::string best;
  int bestDistance = allowed + 1;
  for (const std::string& name : names) {
    const int d = editDistance(typed, name);
    if (d < bestDistance) {
      bestDistance = d;
      best = name;
    }
  }
  return best;
}

}  // namespace rayes
