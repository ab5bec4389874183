// `penumbra-display-study (--scene FILE | --model NAME [--triangles N] [--rest]) [--samples N]
// [--seed S] [--threads T] [--study-tolerance X] [--study-spacing S] [--json OUT]` (docs/BENCHMARKS.md "A display mesh without the DM's vertices"): a
// design study for issue 35 (the product now meshes such floors from their squares:
// core/mesh/lattice_mesh_memo.h; the study varies its tolerance and spacing, with no cap on a
// square's points). It builds the scene's engine and display mesh,
// takes the receiver with the most DM vertices (the floor under a model), and meshes that
// receiver a second way: its lattice squares, refined by the same tests (core/mesh/
// cell_refinement.h) with the exact value at every point (the occluder list of the DM-tree cell
// the point lies in), but holding no DM vertex or edge. It prints both meshes' vertices and
// exact evaluations, and each one's error at random points of the receiver against the exact
// value there, relative to the local unshadowed level (what the tolerance is relative to).
// Scenes with one light only (its factor is compared); a scene with contact lines on the
// receiver (a model resting on it) has value jumps the second mesh does not follow.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/lib/mesh_sampling.h"
#include "core/engine/engine.h"
#include "core/engine/seconds_since.h"
#include "core/geom/convex2d.h"
#include "core/illum/backprojection.h"
#include "core/mesh/cell_triangulation.h"
#include "core/mesh/lattice_split.h"
#include "core/util/parallel.h"
#include "protocol/scene_json.h"
#include "scenegen/model_scene.h"

using namespace penumbra;

namespace {

struct Options {
  std::string scenePath, model;
  int triangles = 0;
  bool rest = false;
  size_t samples = 20000;
  uint64_t seed = 1;
  int threads = 2;
  double studyTolerance = 0;  // 0: the product's tolerance
  double studySpacing = 0;    // 0: the product's lattice spacing
  std::string jsonOut;        // empty: no JSON file
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string name = argv[i];
    if (name == "--rest") {
      o.rest = true;
      continue;
    }
    if (i + 1 >= argc) throw std::invalid_argument(name + " needs a value");
    const std::string value = argv[++i];
    if (name == "--scene") o.scenePath = value;
    else if (name == "--model") o.model = value;
    else if (name == "--triangles") o.triangles = std::stoi(value);
    else if (name == "--samples") o.samples = std::stoul(value);
    else if (name == "--seed") o.seed = std::stoull(value);
    else if (name == "--threads") o.threads = std::stoi(value);
    else if (name == "--study-tolerance") o.studyTolerance = std::stod(value);
    else if (name == "--study-spacing") o.studySpacing = std::stod(value);
    else if (name == "--json") o.jsonOut = value;
    else throw std::invalid_argument("unknown option " + name);
  }
  if (o.scenePath.empty() == o.model.empty()) throw std::invalid_argument("give --scene FILE or --model NAME");
  return o;
}

Scene loadScene(const Options& o) {
  if (!o.scenePath.empty()) return protocol::loadSceneFile(o.scenePath);
  ModelSceneOptions options;
  const auto kind = modelKindFromName(o.model);
  if (!kind) throw std::invalid_argument("--model must be one of " + modelKindNames());
  options.kind = *kind;
  options.triangles = o.triangles;
  options.rest = o.rest;
  return makeModelScene(options);
}

// Light 0's exact factor and unshadowed factor at q of the receiver, as the DM-tree cell
// holding q sees it; counts the evaluations.
class ExactOnReceiver {
 public:
  ExactOnReceiver(const Scene& scene, const Engine::Receiver& receiver) : scene_(scene), receiver_(receiver) {}

  VertexLight value(const Vec2& q) const {
    ++evaluations_;
    const OccluderList& list = receiver_.tree.occluders(receiver_.tree.locate(q));
    const Vec3 n = receiver_.frame.normal;
    return illuminateVertex(scene_, 0, receiver_.frame.to3D(q), n, n, {&list});
  }
  double unshadowed(const Vec2& q) const {
    thread_local Backprojection view;
    const Vec3 n = receiver_.frame.normal;
    view.reset(scene_, 0, receiver_.frame.to3D(q), n, n);
    return view.applies() ? view.unoccludedFactor() : 0.0;
  }
  size_t evaluations() const { return evaluations_; }

 private:
  const Scene& scene_;
  const Engine::Receiver& receiver_;
  mutable std::atomic<size_t> evaluations_{0};
};

// The receiver's lattice squares, each refined by the display's tests with no DM vertex in it.
struct LatticeMesh {
  double spacing = 0;
  std::vector<PieceRefinement> pieces;
  std::multimap<std::pair<int64_t, int64_t>, size_t> pieceAt;  // lattice square → pieces
  size_t capped = 0;

  std::pair<int64_t, int64_t> squareOf(const Vec2& q) const {
    return {int64_t(std::floor(q.x / spacing)), int64_t(std::floor(q.y / spacing))};
  }
  // Light 0's interpolated factor at q, or NaN if no triangle holds it.
  double at(const Vec2& q) const {
    const auto [first, last] = pieceAt.equal_range(squareOf(q));
    for (auto it = first; it != last; ++it) {
      const PieceRefinement& piece = pieces[it->second];
      for (const auto& t : piece.triangles) {
        const Vec2 a = piece.points[t[0]], b = piece.points[t[1]], c = piece.points[t[2]];
        const double area = cross2(b - a, c - a);
        if (!(area > 0)) continue;
        const double u = cross2(c - b, q - b) / area, v = cross2(a - c, q - c) / area, w = 1 - u - v;
        if (u < -1e-9 || v < -1e-9 || w < -1e-9) continue;
        return u * piece.values[t[0] * piece.lights].factor() + v * piece.values[t[1] * piece.lights].factor() +
               w * piece.values[t[2] * piece.lights].factor();
      }
    }
    return std::nan("");
  }
};

LatticeMesh latticeMesh(const Polygon2& outline, const MeshGrid& grid, const ExactOnReceiver& exact, double eps,
                        int threads) {
  LatticeMesh out;
  out.spacing = grid.spacing;
  const std::vector<Polygon2> squares = splitByLattice(outline, grid.spacing, eps);
  out.pieces.resize(squares.size());
  RefineSettings settings = grid.refine;
  settings.maxPoints = 1u << 20;  // no cap: how many points the tests ask for is the question
  std::atomic<size_t> capped{0};
  Parallel(threads).forEach(squares.size(), [&](size_t s) {
    PieceRefinement& piece = out.pieces[s];
    piece.lights = 1;
    piece.points.assign(squares[s].begin(), squares[s].end());
    const CellFan fan = fanOfConvexCell(squares[s], eps);
    if (fan.usesCentre()) piece.points.push_back(areaCentroid(squares[s]));
    for (const Vec2& q : piece.points) piece.values.push_back(exact.value(q));
    const uint32_t loop = uint32_t(squares[s].size());
    for (uint32_t t = 0; t < fan.triangleCount(loop); ++t) piece.triangles.push_back(fan.triangle(loop, t));
    refinePiece(
        piece, settings, [&](const Vec2& q, std::vector<VertexLight>& values) { values.push_back(exact.value(q)); },
        [&](const Vec2& q, std::vector<double>& levels) { levels.push_back(exact.unshadowed(q)); });
    if (piece.capped) ++capped;
  });
  out.capped = capped;
  for (size_t s = 0; s < squares.size(); ++s) out.pieceAt.insert({out.squareOf(areaCentroid(squares[s])), s});
  return out;
}

// Errors at sample points, relative to the local unshadowed factor: the largest, and the
// counts over 0.5 %, 1 % and 2 % of it.
struct ErrorTally {
  double worst = 0;
  size_t over05 = 0, over1 = 0, over2 = 0, missing = 0;
  void add(double interpolated, double exact, double level) {
    if (std::isnan(interpolated)) return void(++missing);
    const double e = level > 0 ? std::abs(interpolated - exact) / level : 0;
    worst = std::max(worst, e);
    over05 += e > 0.005, over1 += e > 0.01, over2 += e > 0.02;
  }
  nlohmann::json json() const {
    return {{"worst", worst}, {"over_0_5pct", over05}, {"over_1pct", over1}, {"over_2pct", over2}, {"missing", missing}};
  }
};

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  const Scene scene = loadScene(o);
  // The product's mesh sums its lights; the study compares one light's factor.
  if (scene.lights().size() != 1) throw std::invalid_argument("the study needs a scene with one light");
  EngineSettings settings;
  settings.threads = o.threads;
  const auto start = std::chrono::steady_clock::now();
  Engine engine(scene, settings);
  const Mesh mesh = engine.mesh();
  const double buildSeconds = secondsSince(start);

  // The receiver with the most DM vertices.
  const Engine::Receiver* receiver = nullptr;
  for (const Engine::Receiver& r : engine.receivers())
    if (!receiver || r.tree.vertices().size() > receiver->tree.vertices().size()) receiver = &r;
  const ReceiverMesh* display = nullptr;
  for (const ReceiverMesh& part : mesh.receivers)
    if (part.face == receiver->face) display = &part;
  if (!display) throw std::runtime_error("the receiver has no display mesh");
  const Face& face = *std::find_if(scene.faces().begin(), scene.faces().end(),
                                   [&](const Face& f) { return f.id == receiver->face; });
  Polygon2 outline;
  for (const Vec3& v : face.polygon) outline.push_back(receiver->frame.to2D(v));
  if (signedArea(outline) < 0) std::reverse(outline.begin(), outline.end());

  const ExactOnReceiver exact(scene, *receiver);
  const auto studyStart = std::chrono::steady_clock::now();
  MeshGrid grid = engine.meshGrid();
  if (o.studyTolerance > 0) grid.refine.tolerance = o.studyTolerance;
  if (o.studySpacing > 0) grid.spacing = o.studySpacing;
  const LatticeMesh lattice = latticeMesh(outline, grid, exact, scene.tolerance().length(), o.threads);
  const double studySeconds = secondsSince(studyStart);
  const size_t studyEvaluations = exact.evaluations();
  size_t studyPoints = 0, studyTriangles = 0;
  for (const PieceRefinement& piece : lattice.pieces) studyPoints += piece.points.size(), studyTriangles += piece.triangles.size();

  // Random points of the receiver (rejection from its box), each mesh against the exact value.
  Vec2 low = outline[0], high = outline[0];
  for (const Vec2& v : outline) low = glm::min(low, v), high = glm::max(high, v);
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> ux(low.x, high.x), uy(low.y, high.y);
  const MeshInterpolator current(mesh);
  const double radiance = std::max({scene.lights()[0].radiance.x, scene.lights()[0].radiance.y, scene.lights()[0].radiance.z});
  ErrorTally currentErrors, studyErrors;
  for (size_t k = 0; k < o.samples;) {
    const Vec2 q(ux(rng), uy(rng));
    if (!contains(outline, q, 0)) continue;
    ++k;
    const double value = exact.value(q).factor(), level = exact.unshadowed(q);
    const auto meshValue = current.at(receiver->face, receiver->frame.to3D(q));
    currentErrors.add(meshValue ? std::max({meshValue->x, meshValue->y, meshValue->z}) / radiance : std::nan(""),
                      value, level);
    studyErrors.add(lattice.at(q), value, level);
  }

  std::printf("scene: %s; build %.2f s at %d threads, receiver %s face %u: %zu DM vertices\n",
              o.scenePath.empty() ? (o.model + " " + std::to_string(o.triangles) + (o.rest ? " rest" : "")).c_str()
                                  : o.scenePath.c_str(),
              buildSeconds, o.threads, scene.object(receiver->face.object).id.c_str(), receiver->face.face,
              receiver->tree.vertices().size());
  std::printf("%-34s %10s %10s %12s %9s %9s %9s %9s %8s\n", "display mesh", "vertices", "triangles", "evaluations",
              "worst %", ">0.5%", ">1%", ">2%", "missed");
  std::printf("%-34s %10zu %10zu %12s %9.3f %9zu %9zu %9zu %8zu\n", "the product's mesh",
              display->positions.size(), display->triangles.size(), "-", 100 * currentErrors.worst, currentErrors.over05,
              currentErrors.over1, currentErrors.over2, currentErrors.missing);
  std::printf("%-34s %10zu %10zu %12zu %9.3f %9zu %9zu %9zu %8zu\n", "lattice squares, refined (study)", studyPoints,
              studyTriangles, studyEvaluations, 100 * studyErrors.worst, studyErrors.over05, studyErrors.over1,
              studyErrors.over2, studyErrors.missing);
  std::printf("study: %.2f s at %d threads, %zu squares of %.4g, tolerance %.4g (the product's: %.4g, %.4g), %zu capped; "
              "%zu samples; the product's evaluations are in its build\n",
              studySeconds, o.threads, lattice.pieces.size(), grid.spacing, grid.refine.tolerance,
              engine.meshGrid().spacing, engine.meshGrid().refine.tolerance, lattice.capped, o.samples);
  if (!o.jsonOut.empty()) {
    const nlohmann::json out = {
        {"build_seconds", buildSeconds},
        {"dm_vertices", receiver->tree.vertices().size()},
        {"samples", o.samples},
        {"product", {{"vertices", display->positions.size()}, {"triangles", display->triangles.size()},
                     {"errors", currentErrors.json()}}},
        {"study", {{"vertices", studyPoints}, {"triangles", studyTriangles}, {"evaluations", studyEvaluations},
                   {"seconds", studySeconds}, {"spacing", grid.spacing}, {"tolerance", grid.refine.tolerance},
                   {"capped", lattice.capped}, {"errors", studyErrors.json()}}}};
    std::ofstream(o.jsonOut) << out.dump(2) << "\n";
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "penumbra-display-study: %s\n", e.what());
  return 1;
}
