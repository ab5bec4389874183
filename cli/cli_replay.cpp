// `penumbra replay SCENE EDITS.jsonl`: applies an edit script frame by frame with
// Engine::apply, prints what each frame cost, and with --verify checks each (or
// every K-th) frame against a full rebuild of the resulting scene.
//
// The whole script is checked before anything is applied: every line is parsed
// (key paths), then every frame is played on a copy of the scene model (unknown
// ids, duplicate ids, degenerate faces). A bad script exits 2 naming the line and
// the key path, and no frame is applied, no file written. --report writes the replay report
// (schema: protocol/replay_report_json.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "cli/commands.h"
#include "cli/progress_bar.h"
#include "core/engine/engine.h"
#include "core/engine/light_edits.h"
#include "core/engine/seconds_since.h"
#include "core/engine/volume_edits.h"
#include "core/illum/face_lookup.h"
#include "core/illum/vertex_illumination.h"
#include "protocol/edits_json.h"
#include "protocol/json_text.h"
#include "protocol/mesh_json.h"
#include "protocol/replay_report_json.h"
#include "protocol/scene_json.h"

namespace penumbra::cli {

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

constexpr size_t kVerifyAllMaxFaces = 200;  // smaller scenes are verified every frame
constexpr double kRelative = 1e-9;          // DESIGN.md invariant 1/3
constexpr double kOfPeak = 1e-12;

// Plays a frame on the scene model the way Engine::apply checks it (edits in
// order, each on the result of the previous), throwing EditError.
void playOnScene(Scene& scene, const Frame& frame) {
  for (size_t i = 0; i < frame.edits.size(); ++i) {
    const Edit& edit = frame.edits[i];
    try {
      if (VolumeEditCheck volumes(scene); volumes.concerns(edit)) {  // as Engine::checkFrame
        volumes.check(edit, i,
                      [&](const std::string& id) { return scene.findObject(id).has_value(); });
        applyVolumeEdit(scene, edit);
        continue;
      }
      if (isLightEdit(edit)) {
        std::vector<Light> lights = scene.lights();
        checkLightEdit(scene, edit, i, lights);  // the edit volume too, as Engine::apply
        applyLightEdit(scene, edit);
        continue;
      }
      if (edit.op == Edit::Op::Add) {
        if (scene.findObject(edit.object.id) || scene.findVolume(edit.object.id))
          throw EditError(i, "object.id", "duplicate object id '" + edit.object.id + "'");
        scene.addObject(edit.object);
        continue;
      }
      const auto index = scene.findObject(edit.id);
      if (!index) throw EditError(i, "id", "unknown object '" + edit.id + "'");
      if (edit.op == Edit::Op::Move)
        scene.setTransform(scene.handleOf(*index), edit.transform);
      else
        scene.removeObject(scene.handleOf(*index));
    } catch (const EditError&) {
      throw;
    } catch (const std::invalid_argument& error) {
      throw EditError(i, edit.op == Edit::Op::Add ? "object" : "transform", error.what());
    }
  }
}

double segmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double t = std::clamp(glm::dot(p - a, ab) / std::max(glm::dot(ab, ab), 1e-300), 0.0, 1.0);
  return glm::length(p - (a + t * ab));
}

// The rebuild's value at world point p of its receiver: its own vertex value if
// p is one of its vertices, else lit from the cells whose closure holds p (one
// cell inside, the two sides of an edge on it).
Vec3 rebuiltValueAt(const Engine& rebuilt, const Engine::Receiver& receiver, const Vec3& p,
                    double eps) {
  const DmTree& tree = receiver.tree;
  const Vec2 q = receiver.frame.to2D(p);
  const CellId cell = tree.locate(q);
  const auto loop = tree.mesh().loop(cell);
  for (HalfEdgeId h : loop) {
    const VertexId v = tree.mesh().halfEdge(h).origin;
    if (glm::length(tree.position(v) - q) <= eps) return rebuilt.value(receiver, v).irradiance;
  }
  std::vector<const OccluderList*> lists{&tree.occluders(cell)};
  for (HalfEdgeId h : loop) {
    const Vec2 a = tree.position(tree.mesh().halfEdge(h).origin),
               b = tree.position(tree.mesh().destination(h));
    if (segmentDistance(q, a, b) > eps) continue;
    const CellId other = tree.mesh().halfEdge(HalfEdgeMesh::twin(h)).cell;
    if (other.is_valid()) lists.push_back(&tree.occluders(other));
    break;
  }
  const Vec3 shading = shadingNormalAt(rebuilt.scene(), receiver.face, receiver.frame.normal, p);
  return illuminatePoint(rebuilt.scene(), p, receiver.frame.normal, shading, lists).irradiance;
}

std::string faceName(const Scene& scene, FaceId face) {
  return "'" + scene.object(face.object).id + "' face " + std::to_string(face.face);
}

// The first difference between the incremental engine and a full rebuild of its
// scene: the same receivers, and at every DM vertex of the incremental mesh the
// same value (1e-9 relative, 1e-12 of the peak absolute).
std::optional<std::string> firstDifference(const Engine& incremental, const Engine& rebuilt) {
  const Scene& scene = incremental.scene();
  if (incremental.receivers().size() != rebuilt.receivers().size())
    return std::to_string(incremental.receivers().size()) + " receivers, the rebuild has " +
           std::to_string(rebuilt.receivers().size());
  double peak = 0;
  for (const auto& r : rebuilt.receivers())
    for (VertexId v : r.tree.vertices())
      for (int c = 0; c < 3; ++c) peak = std::max(peak, std::abs(rebuilt.value(r, v).irradiance[c]));
  const double eps = scene.tolerance().length();
  for (const auto& r : incremental.receivers()) {
    const Engine::Receiver* other = rebuilt.receiver(r.face);
    if (!other) return "receiver " + faceName(scene, r.face) + " is not one in the rebuild";
    for (VertexId v : r.tree.vertices()) {
      const Vec3 p = r.frame.to3D(r.tree.position(v));
      const Vec3 a = incremental.value(r, v).irradiance;
      const Vec3 b = rebuiltValueAt(rebuilt, *other, p, eps);
      for (int c = 0; c < 3; ++c) {
        if (std::abs(a[c] - b[c]) <=
            kRelative * std::max(std::abs(a[c]), std::abs(b[c])) + kOfPeak * peak)
          continue;
        char message[256];
        std::snprintf(message, sizeof message,
                      "at (%.9g, %.9g, %.9g): %.17g, the rebuild has %.17g", p.x, p.y, p.z, a[c],
                      b[c]);
        return "receiver " + faceName(scene, r.face) + " vertex " + std::to_string(v.index) + " " +
               message;
      }
    }
  }
  return std::nullopt;
}

// The whole script checked before anything is applied: every line parsed, then every frame
// played on a copy of the scene model. add_volume files are relative to the script.
std::vector<protocol::ScriptFrame> checkedScript(const Scene& scene, const std::string& scriptPath) {
  protocol::VolumeFiles scriptVolumeFiles;
  scriptVolumeFiles.baseDirectory = std::filesystem::path(scriptPath).parent_path().string();
  const std::string text = protocol::readTextFile(scriptPath, protocol::kMaxJsonFileBytes);
  std::vector<protocol::ScriptFrame> frames =
      protocol::readEditScriptFrames(text, &scene.materials(), &scriptVolumeFiles);
  Scene model = scene;
  for (const auto& f : frames) {
    try {
      playOnScene(model, f.frame);
    } catch (const EditError& error) {
      throw protocol::atLine(f.line, error);
    }
  }
  return frames;
}

struct ReplayOptions {
  EngineSettings settings;
  bool verify = false;
  int verifyEvery = 10;
  bool displayMesh = false;  // also time the display mesh, as serve does
};

void printFrameHeader() {
  std::printf("%6s %5s %9s %9s %9s %9s %9s %9s %8s %9s %8s %11s %7s\n", "frame", "line", "version",
              "remove_ms", "add_ms", "relight_ms", "total_ms", "relit", "changed", "created",
              "recv", "rebuild_ms", "ratio");
}

void printFrameRow(const protocol::ReplayFrame& f, size_t number) {
  const FrameResult& result = f.result;
  std::printf("%6zu %5zu %9llu %9.3f %9.3f %9.3f %9.3f %9zu %8zu %9zu %8zu", number, f.line,
              (unsigned long long)result.version, 1e3 * result.seconds.remove,
              1e3 * result.seconds.add, 1e3 * result.seconds.relight, 1e3 * result.seconds.total(),
              result.verticesRelit, result.verticesChanged, result.verticesCreated,
              result.changedReceivers.size());
  if (f.verified)
    std::printf(" %11.3f %7.3f\n", 1e3 * f.rebuildSeconds, result.seconds.total() / f.rebuildSeconds);
  else
    std::printf(" %11s %7s\n", "-", "-");
}

// Applies frame `i` of the script to the engine, timed, and with --verify (every frame of a
// small scene, else every K-th and the last) compares it with a full rebuild; `failure` says
// where the first comparison failed.
protocol::ReplayFrame replayFrame(Engine& engine, const std::vector<protocol::ScriptFrame>& frames,
                                  size_t i, const ReplayOptions& options,
                                  std::optional<std::string>& failure) {
  protocol::ReplayFrame out;
  out.line = frames[i].line;
  const auto applyStart = Clock::now();
  try {
    out.result = engine.apply(frames[i].frame);
  } catch (const EditError& error) {
    throw protocol::atLine(frames[i].line, error);  // the dry run should have caught it
  }
  out.wallSeconds = secondsSince(applyStart);
  if (options.displayMesh) {
    const auto meshStart = Clock::now();
    (void)engine.mesh();
    out.meshSeconds = secondsSince(meshStart);
  }
  out.verified = options.verify && (engine.scene().faces().size() <= kVerifyAllMaxFaces ||
                                    (i + 1) % size_t(options.verifyEvery) == 0 ||
                                    i + 1 == frames.size());
  if (out.verified) {
    const auto rebuildStart = Clock::now();
    const Engine rebuilt(engine.scene(), options.settings);
    out.rebuildSeconds = secondsSince(rebuildStart);
    if (auto difference = firstDifference(engine, rebuilt))
      failure = "frame " + std::to_string(i + 1) + " (line " + std::to_string(frames[i].line) +
                "): incremental result differs from a full rebuild: " + *difference;
  }
  return out;
}

void printTotals(const protocol::ReplayReport& report) {
  const protocol::ReplayTotals totals = protocol::replayTotals(report);
  std::printf(
      "total: %zu frames, %.3f s (remove %.3f, add %.3f, relight %.3f); %zu relit, %zu changed, "
      "%zu created; %zu tree rebuilds (fallback), %zu frames fully rebuilt",
      report.frames.size(), totals.seconds.total(), totals.seconds.remove, totals.seconds.add,
      totals.seconds.relight, totals.relit, totals.changed, totals.created, totals.rebuilds,
      totals.fullRebuilds);
  if (report.displayMesh) std::printf("; display mesh %.3f s", totals.meshSeconds);
  if (totals.verified)
    std::printf("; %zu frames verified, edit / rebuild = %.3f", totals.verified,
                totals.editSecondsVerified / totals.rebuildSeconds);
  std::printf("\n");
}

}  // namespace

int runReplay(const Args& args) {
  args.allowOnly({"verify-every", "report", "out", "threads", "mesh-tolerance"});
  protocol::ReplayReport report;
  report.scene = args.positional(0, "SCENE");
  report.script = args.positional(1, "EDITS.jsonl");
  ReplayOptions options;
  options.verify = args.flag("verify") || args.option("verify-every");
  options.verifyEvery = args.intOption("verify-every", 10, 1, 1 << 30);
  options.displayMesh = report.displayMesh = args.flag("display-mesh");
  const Scene scene = protocol::loadSceneFile(report.scene);
  const std::vector<protocol::ScriptFrame> frames = checkedScript(scene, report.script);

  BuildBars building;
  const auto buildStart = Clock::now();
  options.settings.threads = args.intOption("threads", 0, 0, 1024);
  options.settings.meshTolerance = meshToleranceOption(args);
  Engine engine(scene, options.settings, building.progress());
  report.buildSeconds = secondsSince(buildStart);
  building.finish();
  std::printf("built %zu faces, %zu receivers in %.3f s; replaying %zu frames%s\n",
              engine.scene().faces().size(), engine.receivers().size(), report.buildSeconds,
              frames.size(), options.verify ? " with --verify" : "");
  printFrameHeader();
  ProgressBar progress("replay");
  for (size_t i = 0; i < frames.size() && !report.verifyFailure; ++i) {
    report.frames.push_back(replayFrame(engine, frames, i, options, report.verifyFailure));
    printFrameRow(report.frames.back(), i + 1);
    progress.update(i + 1, frames.size());
  }
  progress.finish();
  printTotals(report);

  if (const auto out = args.option("report")) {
    protocol::writeTextFile(*out, protocol::replayReportToJson(report).dump(2) + "\n");
    std::printf("wrote %s\n", out->c_str());
  }
  if (report.verifyFailure) {
    std::fprintf(stderr, "penumbra: verify failed: %s\n", report.verifyFailure->c_str());
    return 1;
  }
  if (const auto out = args.option("out")) {
    protocol::saveMeshFile(engine.scene(), engine.mesh(),
                           std::filesystem::path(report.scene).filename().string(), *out);
    std::printf("wrote %s\n", out->c_str());
  }
  return 0;
}

}  // namespace penumbra::cli
