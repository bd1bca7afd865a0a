// Greedy selection of skeleton candidates by the surface they see (nonuniform-probe-placement-svo.txt
// §3.1-3.2; the objective R is skeleton.h's).
#include "skeleton_internal.h"

#include <algorithm>

#include "probebake/common/parallel.h"

namespace probebake::placement {

double objective(const QualityMatrix& m, const std::vector<std::size_t>& rows) {
  double total = 0.0;
  for (std::size_t s = 0; s < m.cols; ++s) {
    float best = 0.0f;
    for (std::size_t r : rows) best = std::max(best, m.row(r)[s]);
    total += double(best);
  }
  return total;
}

namespace {

struct Gain {
  long long newly_seen = 0; // samples with q > 0 that no chosen row sees yet
  double objective = 0.0;   // rise of R
};

Gain gain_of(const QualityMatrix& m, std::size_t r, const std::vector<float>& best) {
  Gain g;
  const float* q = m.row(r);
  for (std::size_t s = 0; s < m.cols; ++s) {
    if (q[s] > 0.0f && best[s] == 0.0f) ++g.newly_seen;
    if (q[s] > best[s]) g.objective += double(q[s] - best[s]);
  }
  return g;
}

} // namespace

std::vector<std::size_t> select_greedy(const QualityMatrix& m, int budget, int threads) {
  std::vector<float> best(m.cols, 0.0f);
  std::vector<char> taken(m.rows, 0);
  std::vector<std::size_t> chosen;
  std::vector<Gain> gains(m.rows);
  const std::size_t limit = budget > 0 ? std::min(std::size_t(budget), m.rows) : m.rows;
  while (chosen.size() < limit) {
    parallel_for(m.rows, threads, [&](std::size_t r) { gains[r] = taken[r] ? Gain{} : gain_of(m, r, best); });
    // Lowest index on ties, so the choice does not depend on the thread count.
    std::size_t pick = m.rows;
    for (std::size_t r = 0; r < m.rows; ++r) {
      if (taken[r]) continue;
      const Gain& g = gains[r];
      if (pick == m.rows) {
        pick = r;
        continue;
      }
      const Gain& b = gains[pick];
      const bool better =
          budget > 0 ? g.objective > b.objective
                     : (g.newly_seen > b.newly_seen || (g.newly_seen == b.newly_seen && g.objective > b.objective));
      if (better) pick = r;
    }
    if (pick == m.rows) break;
    const Gain& g = gains[pick];
    if (budget > 0 ? !(g.objective > 0.0) : g.newly_seen == 0) break;
    taken[pick] = 1;
    chosen.push_back(pick);
    const float* q = m.row(pick);
    for (std::size_t s = 0; s < m.cols; ++s) best[s] = std::max(best[s], q[s]);
  }
  return chosen;
}

} // namespace probebake::placement
