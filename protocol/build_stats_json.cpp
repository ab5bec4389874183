#include "protocol/build_stats_json.h"

namespace penumbra::protocol {

nlohmann::json buildStatsToJson(const BuildStats& s) {
  const BuildTimings& t = s.seconds;
  return {{"faces", s.faces},
          {"receivers", s.receivers},
          {"lights", s.lights},
          {"candidate_pairs", s.candidatePairs},
          {"closed_convex_pairs", s.closedConvexPairs},
          {"cast_attempts", s.castAttempts},
          {"pairs_with_shadow", s.pairsWithShadow},
          {"tiles", s.tiles},
          {"order_fragments", s.orderFragments},
          {"tree_nodes", s.treeNodes},
          {"cells", s.cells},
          {"vertices",
           {{"total", s.vertices},
            {"lit", s.litVertices},
            {"penumbra", s.penumbraVertices},
            {"umbra", s.umbraVertices},
            {"not_lit_lattice_display", s.latticeVertices}}},
          {"comparisons_per_vertex", s.comparisonsPerVertex()},
          {"seconds",
           {{"ordering", t.ordering},
            {"cube", t.cube},
            {"casting_and_merging", t.castingAndMerging},
            {"illumination", t.illumination},
            {"triangulation", t.triangulation},
            {"total", t.total()}}}};
}

}  // namespace penumbra::protocol
