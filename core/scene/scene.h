// The scene model: lights, materials, objects as authored, and the world-space
// faces derived from them (stable ids: object handle + face index; handles are
// assigned in order and never reused, so edits never renumber other faces).
// Owned by one writer (the engine or a loader); const access is thread-safe.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/bsdf/microsurface.h"
#include "core/geom/plane.h"
#include "core/geom/polygon.h"
#include "core/geom/tolerance.h"
#include "core/scene/shading_normal.h"
#include "core/scene/transform.h"
#include "core/scene/volume_object.h"

namespace penumbra {

struct ConvexSolid;
struct MeshTopology;

enum class MaterialType { Diffuse, RoughDiffuse, Conductor, Dielectric };

// A surface's reflectance. Diffuse: Lambertian albedo (the DM's irradiance view uses albedo
// for every type). The others are microfacet BSDFs (core/bsdf) seen by the camera only.
struct Material {
  std::string id;
  Vec3 albedo{0.8};
  MaterialType type = MaterialType::Diffuse;
  Vec2 roughness{0.5};                // GGX / Beckmann alpha along x and y
  Vec3 eta{1.657, 0.880, 0.521};      // conductor: complex index eta + i k (aluminium)
  Vec3 k{9.224, 6.270, 4.837};
  double ior = 1.5;                   // dielectric: index inside / outside
  bsdf::Ndf ndf = bsdf::Ndf::GGX;
  bool singleScattering = false;      // microfacet: first bounce only
  bool operator==(const Material&) const = default;
};

struct Light {
  std::string id;
  Polygon3 polygon;  // convex, planar, counter-clockwise seen from its emitting front
  Vec3 radiance{0.0};

  Plane plane() const;  // front = emitting side
  double area() const { return penumbra::area(polygon); }
};

struct Object {
  std::string id;
  std::vector<Vec3> vertices;             // object space
  std::vector<std::vector<int>> faces;    // indices into vertices, CCW from the front
  // Smooth shading (optional): per face, one object-space normal per corner, in the face's
  // order; empty when the object is shaded flat (core/scene/shading_normal.h).
  std::vector<std::vector<Vec3>> normals;
  std::string material;                   // empty: default material
  bool isStatic = false;
  Transform transform;
};

struct Camera {
  enum class Projection { Perspective, Orthographic };
  Vec3 position{0, 1.5, 6};
  Vec3 target{0, 1, 0};
  Vec3 up{0, 1, 0};
  Projection projection = Projection::Perspective;
  double fovYDeg = 45;  // perspective: full vertical field of view
  double height = 2;    // orthographic: full vertical extent
  double near = 0.1;
  double far = 100;
};

struct FaceId {
  uint32_t object = 0;  // the object's stable handle (Scene::handleOf; never reused)
  uint32_t face = 0;    // index into that object's faces
  bool operator==(const FaceId&) const = default;
  auto operator<=>(const FaceId&) const = default;
};

// An occluder that is a whole closed convex object, not one of its faces (core/shadow/
// object_shadow.h): FaceId{handle, kWholeObject}. It sorts after the object's faces.
inline constexpr uint32_t kWholeObject = 0xfffffffeu;
inline FaceId wholeObject(uint32_t handle) { return FaceId{handle, kWholeObject}; }
inline bool isWholeObject(FaceId id) { return id.face == kWholeObject && id.object != 0xffffffffu; }

// A face the scene refuses (degenerate, thinner than Tolerance::minFaceWidth()):
// which face of which object (its index in objects(), or kUnknown when checked
// alone), and the problem in words ("face is degenerate ...").
class FaceError : public std::invalid_argument {
 public:
  static constexpr size_t kUnknown = size_t(-1);
  FaceError(const std::string& objectId, size_t objectIndex, uint32_t face, std::string problem)
      : std::invalid_argument("object '" + objectId + "' face " + std::to_string(face) + ": " + problem),
        objectId_(objectId), objectIndex_(objectIndex), face_(face), problem_(std::move(problem)) {}
  FaceError atObject(size_t objectIndex) const { return FaceError(objectId_, objectIndex, face_, problem_); }
  size_t objectIndex() const { return objectIndex_; }
  uint32_t face() const { return face_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string objectId_;
  size_t objectIndex_;
  uint32_t face_;
  std::string problem_;
};

struct Face {
  FaceId id;
  // World space, CCW seen from the front, on `plane` within Tolerance::snap(): a face
  // off it by more (the format allows 1e-6 of the face's size) is projected onto its
  // Newell plane, so every later predicate sees a face lying on its own plane.
  Polygon3 polygon;
  Plane plane;       // front normal
  double area = 0;
  // World-space unit shading normals, one per polygon corner, each strictly in front of
  // `plane`; empty: the face is shaded with plane.normal (shading_normal.h).
  std::vector<Vec3> cornerNormals;
};

// The normal a point of `face` is shaded with: its corner normals interpolated at p, or the
// face's own normal when it has none (shading_normal.h).
inline Vec3 shadingNormal(const Face& face, const Vec3& p) {
  return face.cornerNormals.empty() ? face.plane.normal
                                    : interpolatedNormal(face.polygon, face.cornerNormals, face.plane.normal, p);
}

// Where a light lies relative to a face's plane (DESIGN.md "Faces").
enum class FaceClass { Front, Offending, Back };

struct Bounds {
  Vec3 min{0.0}, max{0.0};
  double diagonal() const { return glm::length(max - min); }
  Vec3 center() const { return 0.5 * (min + max); }
};

class Scene {
 public:
  Scene() = default;
  // Throws std::invalid_argument if an object names an unknown material or a
  // face index is out of range, FaceError (with the object's index) for a face the
  // scene's tolerance cannot hold (degenerate, or thinner than minFaceWidth()).
  // protocol validates before this with key paths.
  Scene(std::vector<Light> lights, std::vector<Material> materials,
        std::vector<Object> objects, std::optional<Camera> camera = std::nullopt,
        std::vector<VolumeObject> volumes = {});

  const std::vector<Light>& lights() const { return lights_; }
  const std::vector<Material>& materials() const { return materials_; }
  const std::vector<Object>& objects() const { return objects_; }
  // Stable handles: objects() is ordered by handle; a loaded scene's handles are
  // 0..n-1, objects added later get new ones.
  uint32_t handleOf(size_t objectIndex) const { return handles_[objectIndex]; }
  uint32_t nextHandle() const { return nextHandle_; }  // the handle the next added object gets
  // Gives the objects the handles of the scene this one copies (a scene read back from JSON,
  // which holds no handles, numbers its objects 0..n-1): one per object, increasing, each below
  // `nextHandle`; else throws std::invalid_argument and changes nothing.
  void setHandles(std::vector<uint32_t> handles, uint32_t nextHandle);
  std::optional<size_t> indexOfHandle(uint32_t handle) const;
  const Object& object(uint32_t handle) const;
  const std::optional<Camera>& camera() const { return camera_; }
  // Volume objects: render-time isosurfaces, not DM occluders or receivers (volume_object.h).
  // They do not enter bounds() or tolerance(): adding one leaves the DM as it was.
  const std::vector<VolumeObject>& volumes() const { return volumes_; }
  std::optional<size_t> findVolume(std::string_view id) const;  // index into volumes()
  // Volume edits (core/engine/volume_edits.h): render-time only, so faces, bounds and
  // tolerance stay as they are. Throw std::invalid_argument, changing nothing, on a
  // duplicate id (of any object), no data, an unknown material or a bad index.
  void addVolume(VolumeObject volume);
  void removeVolume(size_t index);
  void setVolumeTransform(size_t index, const Transform& transform);
  void setVolumeIsovalue(size_t index, double isovalue);
  // All faces of all objects in world space, ordered by (object, face).
  const std::vector<Face>& faces() const { return faces_; }
  // The world faces of the object with this handle (empty for an unknown handle).
  std::span<const Face> facesOfObject(uint32_t handle) const;

  // Whether the object is closed and convex (core/scene/closed_convex.h), decided when
  // it enters the scene or moves. Such an object never shadows itself.
  bool isClosedConvex(uint32_t handle) const { return convexSolid(handle) != nullptr; }
  // A closed convex object's solid (convex_solid.h), nullptr for any other handle.
  const ConvexSolid* convexSolid(uint32_t handle) const;
  // Any other object's mesh (mesh_topology.h), nullptr for a closed convex object, a
  // mesh of under 32 faces, or an unknown handle.
  const MeshTopology* meshTopology(uint32_t handle) const;
  // Whether the object may cast on a receiver as one occluder (object_shadow.h).
  bool castsWhole(uint32_t handle) const { return convexSolid(handle) || meshTopology(handle); }
  // False when both faces belong to one closed convex object: neither can shadow the
  // other, so the engine never casts the pair.
  bool mayShadow(FaceId occluder, FaceId receiver) const {
    return occluder.object != receiver.object || !isClosedConvex(occluder.object);
  }

  std::optional<size_t> findObject(std::string_view id) const;  // index into objects()
  std::optional<size_t> findLight(std::string_view id) const;   // index into lights()
  std::optional<size_t> findMaterial(std::string_view id) const;
  // Albedo of a face's object (the default material when it names none).
  Vec3 albedo(FaceId face) const;

  Bounds bounds() const { return bounds_; }
  Tolerance tolerance() const { return tolerance_; }

  FaceClass classify(const Face& face, const Light& light) const;
  // A face receives light if some light is at least partly in front of it.
  bool receivesLight(const Face& face) const;

  // World-space polygons of one object's faces (winding fixed for mirrors).
  static std::vector<Polygon3> worldPolygons(const Object& object);

  // Edits (the engine's, after it has validated them). Bounds and tolerance stay
  // those of the scene as constructed: every geometric decision keeps one scale.
  // Throw std::invalid_argument (changing nothing) on an unknown material, a bad
  // face index, a degenerate or too thin world face (FaceError), a duplicate id or an
  // unknown handle.
  uint32_t addObject(Object object);
  void removeObject(uint32_t handle);
  void setTransform(uint32_t handle, const Transform& transform);
  // The world faces an object would have (checks it like addObject; FaceError
  // with objectIndex() == kUnknown).
  std::vector<Face> facesOf(const Object& object, uint32_t handle) const;
  // Replaces light `index`'s polygon and radiance (its id stays). Bounds and tolerance
  // stay as constructed, as for object edits. Throws std::invalid_argument (changing
  // nothing) for a bad index, a new polygon lightProblem() refuses or a radianceProblem().
  void setLight(size_t index, const Polygon3& polygon, const Vec3& radiance);
  // Replaces the material of `material.id`, or appends it when the scene has none of that id
  // (materials keep their order). Faces and lights are untouched: no face depends on it.
  void setMaterial(Material material);
  // Appends a light (a new id, a polygon lightProblem() takes, a radiance radianceProblem()
  // takes) / removes light `index` (a scene keeps at least one). Throw std::invalid_argument,
  // changing nothing. Bounds and tolerance stay as constructed.
  void addLight(Light light);
  void removeLight(size_t index);
  // Why a scene with tolerance `tolerance` cannot take this polygon as a light's
  // (degenerate, not planar, not convex, thinner than minFaceWidth()); nullopt if it can.
  static std::optional<std::string> lightProblem(const Polygon3& polygon, const Tolerance& tolerance);
  // Why a light cannot have this radiance (not finite, negative); nullopt if it can.
  static std::optional<std::string> radianceProblem(const Vec3& radiance);
  // Why the scene with tolerance `tolerance` cannot hold this world polygon as a
  // face (degenerate, thinner than minFaceWidth()); nullopt if it can.
  static std::optional<std::string> faceProblem(const Polygon3& world, const Tolerance& tolerance);

 public:
  // What an object casts whole from: a closed convex solid or, for any other object, its mesh.
  struct ObjectShape {
    std::shared_ptr<const ConvexSolid> convex;
    std::shared_ptr<const MeshTopology> mesh;
  };

 private:
  void checkReferences(const Object& object) const;
  void deriveFaces();

  std::vector<Light> lights_;
  std::vector<Material> materials_;
  std::vector<Object> objects_;
  std::vector<uint32_t> handles_;  // parallel to objects_, increasing
  // Parallel to objects_: the solid of each closed convex object, the mesh of the others.
  std::vector<ObjectShape> solids_;
  uint32_t nextHandle_ = 0;
  std::optional<Camera> camera_;
  std::vector<VolumeObject> volumes_;
  std::vector<Face> faces_;
  // Parallel to objects_ plus one: object o's faces are faces_[faceStarts_[o], faceStarts_[o + 1]).
  // Evaluations look an object's faces up once per occluder, so not by searching faces_.
  std::vector<uint32_t> faceStarts_{0};
  Bounds bounds_;
  Tolerance tolerance_;
};

}  // namespace penumbra
