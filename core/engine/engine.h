// The discontinuity-meshing engine of one scene: front-to-back orders and overlap
// cubes per light, a DM-tree per receiving face, vertex illumination, and the
// triangulated lit mesh. The engine owns all shadow state and is the only thing
// that changes it; one writer at a time, const access from several threads is safe.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "core/dmtree/dm_tree.h"
#include "core/engine/build_stats.h"
#include "core/engine/frame.h"
#include "core/engine/frame_plan.h"
#include "core/engine/resource_budget.h"
#include "core/geom/plane_frame.h"
#include "core/illum/per_light_values.h"
#include "core/illum/vertex_illumination.h"
#include "core/mesh/display_mesh_memo.h"
#include "core/mesh/mesh.h"
#include "core/order/face_order.h"
#include "core/overlap/overlap_cube.h"
#include "core/scene/scene.h"
#include "core/util/parallel.h"
#include "core/util/shared_progress.h"

namespace penumbra {

struct EngineSettings {
  int overlapGrid = 0;  // tiles per cube side; 0 = chosen from the face count
  // Display subdivision: cells are also cut by a lattice of this spacing (metres)
  // on each face, so smoothly lit regions get vertices too; 0 = the scene's
  // diagonal / kDefaultSpacingDivisions, negative = none (the bare DM cells).
  double meshSpacing = 0;
  static constexpr double kDefaultSpacingDivisions = 32;
  // Display chunks: with a lattice, a receiver's mesh is assembled from square blocks
  // of this many lattice squares a side, each with its own vertices; a later mesh
  // call assembles again only the blocks whose cells changed. 0: chosen at
  // construction from the scene's faces per lattice square (4, 2 or 1, so a block
  // holds some hundreds of cells), < 0: one block.
  int meshChunkSquares = 0;
  // Error-bounded display mesh (core/mesh/cell_refinement.h, docs/DESIGN.md): each piece's
  // triangles are refined until linear interpolation between their corners is within this
  // fraction of each light's local unshadowed level at the test points (edge midpoints,
  // centroids); 0: no refinement (a fan per piece). Edges shorter than the scene's diagonal /
  // meshRefineMinEdgeDivisions are not halved, and a piece stops at kRefineMaxPoints points
  // (counted: Mesh::cappedCells). On by default: what a person sees is within the tolerance.
  static constexpr double kRecommendedMeshTolerance = 0.005;
  double meshTolerance = kRecommendedMeshTolerance;
  double meshRefineMinEdgeDivisions = 4096;
  static constexpr uint32_t kRefineMaxPoints = 1024;
  // Lattice display (core/mesh/lattice_display_rule.h, docs/DESIGN.md): a flat receiver with
  // no contact whose DM holds more than this many vertices in one lattice square is meshed
  // from its lattice squares, refined, instead of its DM cells; 0: never.
  static constexpr uint32_t kDefaultLatticeAbove = 1000;
  uint32_t meshLatticeAbove = kDefaultLatticeAbove;
  // Test hook (failure injection, tests/server/frame_failure_property_test.cpp): called at
  // named points of apply() ("removed", "added", "relight", "rebuild": its whole-engine
  // fallback) and of a server session's meshing ("meshing"); it may throw to simulate a
  // failure there. Empty outside tests.
  std::function<void(const char* point)> failurePoint;
  // Threads for the build (orders and cubes per light, casting per receiver, illumination per
  // vertex) and for meshing (per receiver): 0 = every core, 1 = the calling thread only. The
  // results are bit for bit the same for any count.
  int threads = 0;
  // A closed convex occluder's VE/EV lines only where its element may be on a
  // silhouette from the light (core/shadow/convex_silhouette.h); the others bound no
  // change in the light seen. false: every line, as cast face by face (comparisons).
  bool silhouetteLinesOnly = true;
  // A closed convex object wholly off a receiver's plane and in front of the light's casts
  // on it as one occluder, from its silhouette (core/shadow/object_shadow.h): one list
  // entry (wholeObject(handle)) and only its silhouette lines instead of every face's
  // regions and lines. false: face by face (comparisons; regression tests pinned to it).
  bool closedObjectsAsOne = true;
  // A cell in a light's umbra is not split by later occluders' lines nor listed with them
  // (DmTree::insert); removing the umbra casts them again there. false: every shadow
  // splits every cell it reaches (comparisons).
  bool umbraCulling = true;
  // Per-scene resource limits, checked while building and applying frames: passing
  // one throws ResourceLimitError naming it (README "Resource limits").
  ResourceLimits limits;
};

// Called with (step name, done, total) as a long build proceeds; may be empty.
using EngineProgress = StepProgress;

class Engine {
 public:
  // The build's "illumination" step counts vertices lit, reported every this many.
  static constexpr size_t kVerticesPerBeat = 64;
  // Throws ResourceLimitError as soon as the build passes one of settings.limits.
  explicit Engine(Scene scene, EngineSettings settings = {}, const EngineProgress& progress = {});

  const Scene& scene() const { return scene_; }
  const EngineSettings& settings() const { return settings_; }
  // Counters and timings of the full build (the constructor, or apply()'s whole-engine
  // fallback); apply() reports its own work in FrameResult and leaves these alone,
  // except mesh(), which records its triangulation time here.
  const BuildStats& stats() const { return stats_; }
  // 0 after the build, +1 per applied frame.
  uint64_t version() const { return version_; }
  // Continues another engine's numbering (a server session rebuilding a failed engine).
  void setVersion(uint64_t version) { version_ = version; }

  // Applies a frame's edits together and relights once (paper §3): the removed and
  // moved objects' faces leave the orders, cubes and the DM-trees they cast on (node
  // deletion); the added and moved ones enter them and cast both ways with the faces
  // sharing their tiles; only the vertices those changes created or re-covered are
  // relit. Checks every edit first (including that moved and added objects stay in
  // the overlap cubes' edit volume): on any invalid one, throws EditError and changes
  // nothing. A receiver whose node deletion fails is rebuilt alone (counted in
  // FrameResult::treeRebuilds); an unexpected failure mid-frame rebuilds the engine.
  // Resources: a frame that would pass limits.faces throws ResourceLimitError from
  // checkFrame (nothing changed); passing another limit mid-frame throws it at once
  // (as does std::bad_alloc: neither is retried by a rebuild), and the engine is then
  // unusable: usable() is false and apply() throws std::logic_error; rebuild it from
  // the previous scene. An unexpected exception from that rebuild leaves it half-edited
  // too: discard it (SceneSession restores one).
  // Light edits: a set_light with a new polygon, an add_light or a remove_light rebuilds
  // the whole engine for the edited scene (FrameResult::fullRebuild); a new radiance
  // alone sums every vertex's stored per-light factors again
  // (FrameResult::radianceChanged), no geometry work.
  FrameResult apply(const Frame& frame);
  // False after apply() failed part-way (see apply()).
  bool usable() const { return usable_; }
  // The DM-trees' totals as counted against settings.limits (exact after a build or frame).
  TreeUsage resourceUsage() const { return budget_.totals(); }
  // The DM vertices the last apply() relit, per receiver (sorted ids).
  const std::map<FaceId, std::vector<VertexId>>& lastRelit() const { return lastRelit_; }

  // Checks every edit of a frame in order against the scene as the earlier edits leave
  // it, without copying the scene: ids, transforms and added objects (faces as
  // Scene::addObject makes them), light edits (light_edits.h: checkLightEdit), and that
  // every face stays in the overlap cubes (those of the lights as the frame leaves them).
  // Throws EditError naming the edit and key path, or
  // ResourceLimitError if the scene would pass limits.faces.
  void checkFrame(const Frame& frame) const;
  // The scene after a frame, without changing anything (throws EditError).
  Scene sceneAfter(const Frame& frame) const;

  // The receiving faces, in Scene::faces() order.
  struct Receiver {
    FaceId face;
    PlaneFrame frame;  // the 2D frame of its DM-tree
    DmTree tree;
    // Per vertex slot (indexed by VertexId), each light's value at the vertex; the value
    // summed over the lights is Engine::value(), derived from these on each read.
    PerLightValues perLight;  // [vertex][light]
    // Per vertex slot: 1 once its values were computed for the vertex in it, so a slot that
    // holds a vertex the tree did not report as new is still found and lit. A slot never
    // holds another vertex (slots are append-only, positions fixed) unless the tree is
    // rebuilt afresh, which clears every flag.
    std::vector<uint8_t> lit;
    // Meshed from its lattice squares (core/mesh/lattice_display_rule.h, chosen when its tree
    // is lit and after each frame that touches it): its vertices' values are then not computed
    // or kept (lit stays 0; value() computes one when asked). Flipping back lights them all.
    bool fromLattice = false;
  };
  const std::vector<Receiver>& receivers() const { return receivers_; }
  std::vector<FaceId> receiverFaces() const;  // the receivers' faces, in receivers() order
  // The value at a vertex of a receiver (of this engine): its lights' values summed with the
  // scene's radiances; on a receiver meshed from its lattice squares, computed on each call.
  VertexIrradiance value(const Receiver& receiver, VertexId v) const;
  const Receiver* receiver(FaceId face) const;
  // The receivers a face has cast a shadow on (paper §3.1: removal starts there).
  const std::set<FaceId>& castOn(FaceId occluder) const;

  // Triangulates every cell (cut further by the display lattice, see
  // EngineSettings::meshSpacing). Vertices repeat once per side where the value
  // jumps (contact edges, cells in a light's umbra), so no triangle interpolates
  // across a value discontinuity and umbra cells stay dark. Records its time in stats().
  Mesh mesh(const EngineProgress& progress = {});  // progress: step "triangulation", per cell
  // The same for the listed receivers only (in Scene::faces() order, each once;
  // faces that are not receivers are skipped). Equals the matching part of mesh().
  Mesh mesh(const std::vector<FaceId>& only);
  // One receiver's part of mesh(). Throws std::out_of_range if `face` is not a receiver.
  ReceiverMesh meshOf(FaceId face);
  // Meshing keeps (DisplayMeshMemo), per receiver and per cell, the cell's triangles and the
  // inputs they came from (outline, occluder list and those faces' polygons, corner values); only
  // cells the tree touched since the last call are looked at, and one whose inputs are
  // all equal is kept instead of lit again. A receiver's mesh is the concatenation of
  // its display chunks (EngineSettings::meshChunkSquares; vertices on a chunk border
  // repeat in each chunk); only chunks holding a changed cell are assembled again, in
  // cell order, so the result is bit for bit what a fresh mesh() gives. Counters of
  // the last mesh call:
  using MeshCacheCounters = MeshMemoCounters;
  const MeshCacheCounters& lastMeshCounters() const { return displayMemo_.lastCounters(); }
  // A display chunk of a receiver's mesh: the lattice-aligned block (x, y) of its 2D
  // frame (side meshChunkSquares · meshSpacing()) and the chunk's own mesh.
  using MeshChunkKey = penumbra::MeshChunkKey;
  struct MeshChunk {
    MeshChunkKey key;
    std::shared_ptr<const ReceiverMesh> mesh;  // immutable; shared while the chunk is unchanged
  };
  struct ReceiverChunks {
    FaceId face;
    std::vector<MeshChunk> chunks;  // non-empty chunks, in key order
  };
  // The listed receivers' meshes as their chunks (as mesh(only): Scene::faces() order,
  // each once, non-receivers skipped). A receiver's mesh(only) entry is its chunks'
  // meshes concatenated; a chunk this call did not assemble again is the same object
  // the previous call returned, so a caller can tell what changed without comparing.
  // progress: step "triangulation", per cell (DisplayMeshMemo::update).
  std::vector<ReceiverChunks> meshChunks(const std::vector<FaceId>& only, const EngineProgress& progress = {});
  // Drops the memo: the next mesh call lights every cell afresh.
  void forgetMeshMemo() { displayMemo_.clear(); }

  // The lattice spacing mesh() uses (0: none), and the side of its display chunks in
  // lattice squares (0: one chunk per receiver).
  double meshSpacing() const;
  int meshChunkSquares() const { return meshChunkSquares_; }
  // The lattice, chunks and refinement mesh() uses.
  MeshGrid meshGrid() const;
  // Whether the last mesh call meshed the receiver from its lattice squares
  // (EngineSettings::meshLatticeAbove); false if it was never meshed.
  bool meshedFromLattice(FaceId face) const { return displayMemo_.fromLattice(face); }

  // Casts afresh (and lights) the listed receivers' trees when dead slots dominate them:
  // node deletion leaves dead nodes, vertices and cells behind (the tree and its mesh only
  // append), so a receiver edited again and again would grow without bound. A receiver is
  // cast afresh when its slots exceed kCompactSlotRatio × its live ones (+ a small floor).
  // Its light values are the same; its cells (so its triangulation) may differ. Returns the
  // faces cast afresh (their mesh memo is dropped: the next mesh call re-meshes them).
  static constexpr size_t kCompactSlotRatio = 3;
  // Receivers with at least this many vertex slots get 25 % spare value slots (illuminate).
  static constexpr size_t kHeadroomMinSlots = 4096;
  std::vector<FaceId> compactTrees(const std::vector<FaceId>& faces);

  // Checks every structure the engine holds; throws std::logic_error.
  void validate() const;

 private:
  void build(const EngineProgress& progress);
  // A receiver with an empty DM-tree but the light-plane horizons of every light.
  Receiver makeReceiver(const Face& face) const;
  // Casts `occluder` (a face, or a whole object: castingOccluder in object_shadow.h) on
  // `receiver` from `light` and merges the shadow; records the
  // pair in castOn_/castBy_. Returns nullopt when nothing is shadowed.
  std::optional<InsertResult> castPair(size_t light, FaceId occluder, Receiver& receiver);
  // The same without recording: touches `receiver` (and the thread-safe budget) only, so
  // receivers may cast in parallel.
  std::optional<InsertResult> castInto(size_t light, FaceId occluder, Receiver& receiver,
                                       const std::function<void()>& beat = {});
  // The build's steps (§2.1–2.4); each fills its part of stats_.
  void buildOrdersAndCubes(const EngineProgress& progress);
  void castAndIlluminateAll(std::chrono::steady_clock::time_point start, const EngineProgress& progress);
  void splitStepSeconds(double wall, const std::vector<double>& castSeconds, const std::vector<double>& lightSeconds);
  void countBuild();
  // Casts every candidate occluder of the overlap cubes on one (fresh) receiver.
  void castAllOn(Receiver& receiver);
  // Forgets every cast relation with `face` as receiver.
  void forgetReceived(FaceId face);
  // Sizes the per-slot arrays to the tree's vertex slots.
  void growSlots(Receiver& receiver) const;
  // Decides whether the receiver is meshed from its lattice squares (Receiver::fromLattice),
  // dropping its kept values when it becomes so; returns true when it stops being so (its live
  // vertices then need lighting).
  bool chooseDisplay(Receiver& receiver) const;
  // Lights every vertex of a fresh tree (in parallel over vertices), unless chooseDisplay puts
  // it on its lattice squares. `report` (may be null) grows by the vertices to light and counts
  // them every kVerticesPerBeat, so a receiver of many vertices moves the fraction.
  void illuminate(Receiver& receiver, SharedProgress* report = nullptr) const;
  // A receiver's casts beat the "casting" step every this many (its report counts all receivers').
  static constexpr size_t kCastsPerBeat = 16;
  void relightVertex(Receiver& receiver, VertexId v) const;
  // relightVertex's value alone: writes v's slots only, touches no cell.
  void computeVertex(Receiver& receiver, VertexId v) const;
  // Each light's value at v into `out` (one per light), from the lists of the cells around it.
  void valuesAt(const Receiver& receiver, VertexId v, std::span<VertexLight> out) const;
  // apply()'s phases (paper §3), in order. Each leaves its part of `work` for the next and
  // counts its work in `result`; an exception from any of them makes apply() rebuild.
  // Plans the frame and edits scene_ (apply_frame.cpp).
  FramePlan planFrame(const Frame& frame);
  // REMOVE (§3.1, frame_remove.cpp): the leaving faces quit the orders, cubes and every tree
  // they shadowed; their own trees go.
  void removeLeaving(const FramePlan& plan, FrameWork& work, FrameResult& result);
  // Deletes one leaving occluder's nodes from `target`'s tree (each light); a geometric
  // failure marks `target` for casting afresh.
  void deleteOccluderNodes(FaceId occluder, FaceId target, FrameWork& work, FrameResult& result);
  // ADD (§3.2, frame_add.cpp): the entering faces join the orders and cubes, get trees if
  // they receive light, and cast both ways with the faces sharing their tiles.
  void addEntering(const FramePlan& plan, FrameWork& work, FrameResult& result);
  void placeReceiver(const Face& face, FrameWork& work);  // a fresh tree, in a free slot if any
  void castEntering(size_t light, const std::vector<const Face*>& entering, FrameWork& work);
  void recastFailed(FrameWork& work, FrameResult& result);  // receivers marked for rebuild
  // RELIGHT (§3.3, frame_relight.cpp): every vertex of the relight set once, and any live
  // vertex whose slot holds no value.
  void relightDirty(const FrameWork& work, FrameResult& result);
  // The (occluder → receiver) pairs castOn_ holds; those a planned frame undoes.
  size_t castPairs() const;
  size_t castPairsUndone(const FramePlan& plan) const;
  // The whole engine built afresh for scene_, every receiver reported rebuilt.
  FrameResult rebuildWhole();
  // EngineSettings::failurePoint, when set (tests).
  void reach(const char* point) const {
    if (settings_.failurePoint) settings_.failurePoint(point);
  }
  // Adds to `dirty` what one occluder's node deletion on `receiver` must have relit:
  // the vertices of its changed cells and its new vertices inside the removed
  // penumbra. Outside it the scene did not change for this receiver: a surviving
  // vertex keeps its value, and one re-made at a deleted vertex's exact position
  // takes that vertex's value (node deletion re-splits cells far from the shadow).
  void relightAfterRemoval(FaceId target, Receiver& receiver, const RemoveResult& removed, DirtySet& dirty);
  // Sorts receivers_ by face (Scene::faces() order), drops `dropped`, reindexes.
  void compactReceivers(const std::vector<bool>& dropped);
  // After a radiance-only light edit: every live vertex whose value (summed on read from its
  // stored per-light factors) differs from the one under radianceBefore is counted changed
  // (light_edits.cpp) and every receiver reported changed; no cell is touched (the mesh memo
  // keeps per-light values and sums its chunks again with the new radiances).
  void resumRadiance(const std::vector<Vec3>& radianceBefore, FrameResult& result);
  // Counts every receiver's tree against the limits afresh (drops drift).
  void recountBudget();

  // The listed receivers (Scene::faces() order, each once, non-receivers skipped) as the
  // display memo reads them.
  std::vector<MeshSource> meshSources(const std::vector<FaceId>& only) const;
  std::vector<MeshSource> meshSources() const;  // every receiver
  // Brings the display memo up to date for `sources` (counters of this call).
  void updateDisplayMemo(const std::vector<MeshSource>& sources, const EngineProgress& progress = {});
  void pruneDisplayMemo();  // drops the memos of faces that are no longer receivers

  Scene scene_;
  EngineSettings settings_;
  Parallel parallel_;
  ResourceBudget budget_;
  bool usable_ = true;
  int meshChunkSquares_ = 0;  // fixed at construction: chunks stay comparable across edits
  uint64_t version_ = 0;
  std::vector<std::unique_ptr<FaceOrder>> orders_;   // per light
  std::vector<std::unique_ptr<OverlapCube>> cubes_;  // per light
  std::vector<Receiver> receivers_;
  std::map<FaceId, size_t> receiverIndex_;
  std::map<FaceId, std::set<FaceId>> castOn_;   // occluder -> receivers it shadows
  std::map<FaceId, std::set<FaceId>> castBy_;   // receiver -> occluders shadowing it
  std::map<FaceId, std::vector<VertexId>> lastRelit_;
  BuildStats stats_;
  DisplayMeshMemo displayMemo_;
};

}  // namespace penumbra
