#include "interchange/scene_assembly.h"

#include "protocol/material_json.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "core/geom/polygon.h"
#include "core/geom/tolerance.h"
#include "interchange/coplanar_overlaps.h"
#include "interchange/corner_normals.h"
#include "interchange/default_studio.h"
#include "interchange/light_polygons.h"
#include "interchange/mesh_orientation.h"
#include "interchange/vertex_weld.h"
#include "protocol/scene_json.h"
#include "protocol/utf8.h"

namespace penumbra::interchange {

namespace {

using protocol::ValidationError;
using Json = nlohmann::json;

// Positions closer than this fraction of the scene's diagonal are one vertex.
constexpr double kWeldFraction = 1e-9;

Json toJson(const Vec3& v) { return Json::array({v.x, v.y, v.z}); }

bool isEmissive(const Vec3& e) { return e.x > 0 || e.y > 0 || e.z > 0; }

// The face's vertex cycle rotated to start at its smallest index (one key per face).
IndexPolygon canonical(IndexPolygon p) {
  std::rotate(p.begin(), std::min_element(p.begin(), p.end()), p.end());
  return p;
}

std::string trimmed(const std::string& s) {
  const size_t first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

// Hands out unique ids: "name", then "name.2", "name.3", …
class IdPool {
 public:
  IdPool(std::string fallback, std::string repair, ImportReport& report)
      : fallback_(std::move(fallback)), repair_(std::move(repair)), report_(report) {}
  std::string take(const std::string& wanted) {
    const std::string valid = protocol::replacingInvalidUtf8(wanted);
    if (valid != wanted) report_.count("names_with_invalid_utf8_replaced");
    std::string base = trimmed(valid);
    if (base.empty()) base = fallback_;
    std::string id = base;
    for (int k = 2; used_.count(id); ++k) id = base + "." + std::to_string(k);
    if (id != trimmed(valid)) report_.count(repair_);
    used_.insert(id);
    return id;
  }

 private:
  std::string fallback_, repair_;
  ImportReport& report_;
  std::set<std::string> used_;
};

struct RepairedGroup {
  const ImportedGroup* source = nullptr;
  std::vector<Vec3> positions;  // welded, scaled (and placed in the studio)
  std::vector<IndexPolygon> faces;
  size_t verticesWelded = 0;  // used positions that joined an earlier one
  SurfaceFacts topology;      // of `faces` once oriented (lights: unset)
  std::vector<std::vector<Vec3>> normalsAt;  // the file's normals per position (corner_normals.h)
};

// minWidth: the scene's Tolerance::minFaceWidth() (thinner faces are refused by Scene).
// Emissive groups are not joined here: lightPolygons() joins them once they face the scene.
// Positions are scaled by `scale`, then placed by `place` (identity outside the studio).
RepairedGroup repairGroup(const ImportedGroup& group, bool emissive, double scale, const StudioPlacement& place,
                          double weldEps, double minWidth, ImportReport& report) {
  RepairedGroup out;
  out.source = &group;
  std::vector<Vec3> scaled;
  scaled.reserve(group.positions.size());
  for (const Vec3& p : group.positions) scaled.push_back(place.apply(p * scale));
  WeldResult weld = weldVertices(scaled, weldEps);
  out.normalsAt = fileNormalsAt(group, weld.remap, weld.positions.size());
  out.positions = std::move(weld.positions);

  std::vector<IndexPolygon> pieces;
  std::set<int> used;
  for (const IndexPolygon& polygon : group.polygons) {
    IndexPolygon remapped;
    for (int i : polygon) {
      remapped.push_back(weld.remap[size_t(i)]);
      used.insert(i);
    }
    const PolygonRepair repair = repairPolygon(out.positions, remapped);
    report.count("repeated_polygon_vertices_removed", repair.repeatedVerticesRemoved);
    if (repair.degenerate) report.count("degenerate_polygons_dropped");
    if (repair.selfIntersecting) report.count("self_intersecting_polygons_dropped");
    if (!repair.pieces.empty() && repair.nonPlanar) report.count("non_planar_polygons_split");
    if (!repair.pieces.empty() && !repair.nonPlanar && repair.nonConvex) report.count("non_convex_polygons_split");
    if (repair.pieces.size() > 1) report.count("pieces_added_by_splits", repair.pieces.size() - 1);
    pieces.insert(pieces.end(), repair.pieces.begin(), repair.pieces.end());
  }
  // Used input positions that joined one met earlier (duplicate coordinates).
  size_t joined = 0;
  std::set<int> welded;
  for (int i : used)
    if (!welded.insert(weld.remap[size_t(i)]).second) ++joined;
  report.count("duplicate_vertices_merged", joined);
  out.verticesWelded = joined;
  if (group.joinTriangles && !emissive) report.count("coplanar_triangles_joined", joinCoplanarConvex(out.positions, pieces));
  const size_t before = pieces.size();
  std::erase_if(pieces, [&](const IndexPolygon& piece) {
    Polygon3 points;
    for (int i : piece) points.push_back(out.positions[size_t(i)]);
    return width(points) < minWidth;
  });
  report.count("thin_polygons_dropped", before - pieces.size());

  // Same face twice: dropped. A face and its reverse: a two-sided surface, both kept.
  std::set<IndexPolygon> seen;
  for (IndexPolygon& face : pieces) {
    if (!seen.insert(canonical(face)).second) {
      report.count("duplicate_faces_dropped");
      continue;
    }
    IndexPolygon reversed(face.rbegin(), face.rend());
    if (seen.count(canonical(reversed))) report.count("reverse_wound_duplicates_kept_two_sided");
    out.faces.push_back(std::move(face));
  }
  return out;
}

// The faces of each group as points; lights' groups left empty (lights neither block nor receive).
std::vector<std::vector<Polygon3>> facePolygons(const std::vector<RepairedGroup>& groups,
                                                const std::vector<bool>& isLight) {
  std::vector<std::vector<Polygon3>> polygons(groups.size());
  for (size_t g = 0; g < groups.size(); ++g)
    if (!isLight[g])
      for (const IndexPolygon& face : groups[g].faces) {
        Polygon3& points = polygons[g].emplace_back();
        for (int i : face) points.push_back(groups[g].positions[size_t(i)]);
      }
  return polygons;
}

// Drops the faces the policy drops; afterIndex[g][f] is face f's index once they are gone (-1: dropped).
std::vector<std::vector<int>> dropFaces(std::vector<RepairedGroup>& groups, const CoplanarDecision& decision) {
  std::vector<std::vector<int>> afterIndex(groups.size());
  for (size_t g = 0; g < groups.size(); ++g) {
    std::vector<IndexPolygon> kept;
    for (size_t f = 0; f < groups[g].faces.size(); ++f) {
      const bool drop = decision.dropped.count(FaceRef{g, f}) > 0;
      afterIndex[g].push_back(drop ? -1 : int(kept.size()));
      if (!drop) kept.push_back(std::move(groups[g].faces[f]));
    }
    groups[g].faces = std::move(kept);
  }
  return afterIndex;
}

std::string pointText(const Vec3& p) {
  std::ostringstream text;
  text.precision(6);
  text << "(" << p.x << ", " << p.y << ", " << p.z << ")";
  return text.str();
}

// One warning per dropped face and per overlap kept, naming the faces as the scene has them
// ("'floor' face 0"; a dropped face by its object and centre); at most kMaxWarnings, then a tally.
void warnCoplanar(const CoplanarDecision& decision, const std::vector<std::vector<Polygon3>>& polygons,
                  const std::vector<std::vector<int>>& afterIndex, const std::vector<std::string>& objectIds,
                  ImportReport& report) {
  constexpr size_t kMaxWarnings = 20;
  auto name = [&](const FaceRef& r) {
    const int index = afterIndex[r.group][r.face];
    if (index >= 0) return "'" + objectIds[r.group] + "' face " + std::to_string(index);
    return "a face of '" + objectIds[r.group] + "' around " + pointText(centroid(polygons[r.group][r.face]));
  };
  std::vector<std::string> lines;
  for (const auto& [covered, by] : decision.dropped)
    lines.push_back("coplanar face dropped: " + name(covered) + " lies wholly within " + name(by) +
                    " in the same plane, facing the same way");
  for (const CoplanarOverlap& o : decision.kept) {
    std::ostringstream area;
    area.precision(6);
    area << o.area;
    lines.push_back("coplanar faces overlap: " + name(o.a) + " and " + name(o.b) + " lie in one plane " +
                    (o.backToBack ? "back to back" : "facing the same way") + " and share an area of " +
                    area.str() + "; both kept");
  }
  for (size_t k = 0; k < lines.size() && k < kMaxWarnings; ++k) report.warnings.push_back(lines[k]);
  if (lines.size() > kMaxWarnings)
    report.warnings.push_back("… and " + std::to_string(lines.size() - kMaxWarnings) +
                              " more coplanar faces dropped or overlapping (see the counts)");
}

// Orients every non-light group's faces (mesh_orientation.h) and counts the flips; closed
// components around a light (a room modelled as one closed object) are wound inward.
void orientSurfaces(std::vector<RepairedGroup>& groups, const std::vector<bool>& isLight, ImportReport& report) {
  // Points just inside each light, toward the middle of the other faces (a lamp in a ceiling's
  // plane lies on the room's surface itself).
  Bounds rest{Vec3(INFINITY), Vec3(-INFINITY)};
  for (size_t g = 0; g < groups.size(); ++g)
    if (!isLight[g])
      for (const IndexPolygon& face : groups[g].faces)
        for (int i : face) {
          rest.min = glm::min(rest.min, groups[g].positions[size_t(i)]);
          rest.max = glm::max(rest.max, groups[g].positions[size_t(i)]);
        }
  std::vector<Vec3> lightPoints;
  if (rest.min.x <= rest.max.x)
    for (size_t g = 0; g < groups.size(); ++g)
      if (isLight[g])
        for (const IndexPolygon& face : groups[g].faces) {
          Polygon3 points;
          for (int i : face) points.push_back(groups[g].positions[size_t(i)]);
          const Vec3 c = centroid(points);
          lightPoints.push_back(c + 0.01 * (rest.center() - c));
        }
  for (size_t g = 0; g < groups.size(); ++g) {
    if (isLight[g]) continue;
    RepairedGroup& group = groups[g];
    group.topology = orientFaces(group.positions, group.faces, lightPoints);
    report.count("faces_flipped_for_consistent_orientation", group.topology.facesFlipped);
    report.count("closed_components_turned_outward", group.topology.closedComponentsTurnedOutward);
    report.count("closed_components_facing_inward_around_lights", group.topology.closedComponentsAroundLights);
    report.count("non_orientable_components", group.topology.nonOrientableComponents);
  }
}

// Non-manifold edges are counted and named per object, left as they are.
void warnNonManifold(const std::vector<RepairedGroup>& groups, const std::vector<bool>& isLight,
                     const std::vector<std::string>& objectIds, ImportReport& report) {
  constexpr size_t kMaxWarnings = 20;
  size_t objects = 0;
  for (size_t g = 0; g < groups.size(); ++g) {
    const size_t edges = isLight[g] ? 0 : groups[g].topology.nonManifoldEdges;
    if (!edges) continue;
    report.count("non_manifold_edges", edges);
    if (++objects <= kMaxWarnings)
      report.warnings.push_back("non-manifold edges left as they are: '" + objectIds[g] + "' has " +
                                std::to_string(edges) + (edges == 1 ? " edge" : " edges") +
                                " shared by three or more faces");
  }
  if (objects > kMaxWarnings)
    report.warnings.push_back("… and " + std::to_string(objects - kMaxWarnings) +
                              " more objects with non-manifold edges (see the counts)");
}

// A camera in file units (Penumbra's GLB) scaled as the geometry is; what is not a number is
// left for sceneFromJson to refuse with its path.
Json scaledCamera(Json camera, double scale) {
  for (const char* key : {"position", "target"})
    if (camera.contains(key) && camera[key].is_array())
      for (Json& c : camera[key])
        if (c.is_number()) c = c.get<double>() * scale;
  for (const char* key : {"height", "near", "far"})
    if (camera.contains(key) && camera[key].is_number()) camera[key] = camera[key].get<double>() * scale;
  return camera;
}

}  // namespace

ImportResult assembleScene(const ImportedGeometry& geometry, const ImportOptions& options, ImportReport report) {
  if (!(std::isfinite(options.scale) && options.scale > 0))
    throw ValidationError("scale", "scale must be a positive number");
  if (options.lightRadiance)
    for (int c = 0; c < 3; ++c)
      if (!(std::isfinite((*options.lightRadiance)[c]) && (*options.lightRadiance)[c] >= 0))
        throw ValidationError("light-radiance", "radiance must be three non-negative numbers");

  // Every coordinate finite and within reach of double-precision geometry at 1e-9 (a NaN or a
  // 1e300 would poison the scene's size, the welding grid and every tolerance after it).
  constexpr double kMaxCoordinate = 1e9;  // metres, after scaling
  for (size_t g = 0; g < geometry.groups.size(); ++g)
    for (size_t i = 0; i < geometry.groups[g].positions.size(); ++i) {
      const Vec3 p = geometry.groups[g].positions[i] * options.scale;
      for (int c = 0; c < 3; ++c)
        if (!(std::abs(p[c]) <= kMaxCoordinate))  // false for NaN too
          throw ValidationError("(import).groups[" + std::to_string(g) + "].positions[" +
                                    std::to_string(i) + "]",
                                "vertex coordinate is not a finite number within ±1e9 m");
    }

  // Scene size first: it sets the welding distance.
  Bounds bounds{Vec3(INFINITY), Vec3(-INFINITY)};
  bool anyPosition = false;
  for (const ImportedGroup& group : geometry.groups) {
    if (group.trianglesRead) report.trianglesRead += *group.trianglesRead;
    for (const IndexPolygon& polygon : group.polygons) {
      if (!group.trianglesRead) report.trianglesRead += polygon.size() >= 3 ? polygon.size() - 2 : 0;
      for (int i : polygon) {
        const Vec3 p = group.positions[size_t(i)] * options.scale;
        bounds.min = glm::min(bounds.min, p);
        bounds.max = glm::max(bounds.max, p);
        anyPosition = true;
      }
    }
  }
  report.boundsMin = bounds.min;
  report.boundsMax = bounds.max;
  if (!anyPosition || !(bounds.diagonal() > 0))
    throw ValidationError("(import)", "the file has no faces with area");

  auto emissionOf = [&](const ImportedGroup& g) {
    return g.material >= 0 ? geometry.materials[size_t(g.material)].emission : Vec3(0.0);
  };
  // No emissive faces: the model goes into the default studio, scaled and moved before
  // anything else so that welding and every tolerance see it where it will be.
  const bool fileHasLights = std::any_of(geometry.groups.begin(), geometry.groups.end(), [&](const ImportedGroup& g) {
    return !g.polygons.empty() && isEmissive(emissionOf(g));
  });
  std::optional<StudioPlacement> studio;
  if (!fileHasLights && options.studio) studio = placeInStudio(bounds);
  const StudioPlacement place = studio.value_or(StudioPlacement{});
  const Bounds placed{place.apply(bounds.min), place.apply(bounds.max)};
  const double weldEps = kWeldFraction * placed.diagonal();
  // The studio's room holds the model (at most 2 m, centred), so it sets the scene's size.
  const Tolerance tolerance = Tolerance::forSize(studio ? studioBounds().diagonal() : bounds.diagonal());
  std::vector<RepairedGroup> groups;
  std::vector<bool> isLight;
  for (const ImportedGroup& group : geometry.groups) {
    // Undefined materials count once per group that uses them.
    if (group.material >= 0 && !geometry.materials[size_t(group.material)].defined)
      report.count("groups_with_undefined_material");
    isLight.push_back(isEmissive(emissionOf(group)));
    // Dropping faces only shrinks the scene, and its minimum width with it.
    groups.push_back(
        repairGroup(group, isLight.back(), options.scale, place, weldEps, tolerance.minFaceWidth(), report));
  }

  // Each object's surface wound one way, closed parts outward (README "Import"): before the
  // coplanar test, which tells back-to-back faces from faces facing the same way.
  orientSurfaces(groups, isLight, report);

  // Faces in one plane overlapping (README "Import"): a covered one goes, the others stay; all reported.
  const std::vector<std::vector<Polygon3>> polygons = facePolygons(groups, isLight);
  const CoplanarDecision coplanar = decideCoplanarOverlaps(findCoplanarOverlaps(polygons, tolerance));
  report.count("covered_coplanar_faces_dropped", coplanar.dropped.size());
  report.count("coplanar_overlapping_face_pairs", coplanar.kept.size());
  const std::vector<std::vector<int>> afterIndex = dropFaces(groups, coplanar);
  for (size_t g = 0; g < groups.size(); ++g)
    if (!isLight[g] && groups[g].faces.size() != afterIndex[g].size()) {
      // Faces went: the surface's facts are those of what is left (its flips stand).
      const size_t flipped = groups[g].topology.facesFlipped;
      groups[g].topology = surfaceFacts(groups[g].faces);
      groups[g].topology.facesFlipped = flipped;
    }

  // The centre of what is lit: lights are turned to face it.
  Bounds lit{Vec3(INFINITY), Vec3(-INFINITY)};
  for (const RepairedGroup& g : groups)
    if (!isEmissive(emissionOf(*g.source)))
      for (const IndexPolygon& face : g.faces)
        for (int i : face) {
          lit.min = glm::min(lit.min, g.positions[size_t(i)]);
          lit.max = glm::max(lit.max, g.positions[size_t(i)]);
        }
  const bool anyLit = lit.min.x <= lit.max.x;

  Json lights = Json::array(), objects = Json::array(), materials = Json::object();
  IdPool lightIds("light", "light_ids_made_unique", report);
  IdPool objectIdPool("object", "object_ids_made_unique", report);
  IdPool materialNames("material", "material_names_made_unique", report);
  std::map<int, std::string> usedMaterials;  // imported material → its name in the scene
  std::vector<std::string> objectIds;          // per group: its object's id (its own name if it has none)
  for (const RepairedGroup& g : groups) {
    objectIds.push_back(g.source->name);
    if (g.faces.empty()) {
      if (!g.source->polygons.empty()) report.count("groups_emptied_by_repairs");
      continue;
    }
    const Vec3 emission = emissionOf(*g.source);
    if (isEmissive(emission)) {
      const std::optional<Vec3> litCentre = anyLit ? std::optional(lit.center()) : std::nullopt;
      for (const Polygon3& polygon : lightPolygons(g.positions, g.faces, litCentre, report)) {
        Vec3 radiance = emission;
        if (options.lightRadiance) {
          radiance = *options.lightRadiance;
          report.count("light_radiance_overridden");
        }
        Json points = Json::array();
        for (const Vec3& p : polygon) points.push_back(toJson(p));
        lights.push_back({{"id", lightIds.take(g.source->name)}, {"polygon", points}, {"radiance", toJson(radiance)}});
      }
      continue;
    }
    // Only the vertices the faces use, in first-use order.
    std::map<int, int> compact;
    Json vertices = Json::array(), faces = Json::array();
    for (const IndexPolygon& face : g.faces) {
      Json indices = Json::array();
      for (int i : face) {
        const auto [it, fresh] = compact.emplace(i, int(compact.size()));
        if (fresh) vertices.push_back(toJson(g.positions[size_t(i)]));
        indices.push_back(it->second);
      }
      faces.push_back(indices);
    }
    report.count("unused_vertices_dropped", g.positions.size() - compact.size());
    objectIds.back() = objectIdPool.take(g.source->name);
    Json object = {{"id", objectIds.back()}, {"vertices", vertices}, {"faces", faces}};
    if (!g.normalsAt.empty()) {
      size_t flatCorners = 0;
      object["normals"] = cornerNormalsJson(g.positions, g.faces, g.normalsAt, flatCorners);
      report.count("faces_with_file_normals", g.faces.size());
      report.count("corners_shaded_flat_without_a_file_normal", flatCorners);
    }
    const int m = g.source->material;
    if (m >= 0 && geometry.materials[size_t(m)].defined) {
      if (!usedMaterials.count(m)) usedMaterials[m] = materialNames.take(geometry.materials[size_t(m)].name);
      object["material"] = usedMaterials[m];
    }
    objects.push_back(std::move(object));
    report.faces += g.faces.size();
    report.meshes.push_back(ObjectMeshFacts{objectIds.back(), g.faces.size(), g.verticesWelded,
                                            g.topology.components, g.topology.closedComponents,
                                            g.topology.facesFlipped, g.topology.nonManifoldEdges,
                                            g.topology.boundaryEdges});
  }
  for (const auto& [m, name] : usedMaterials) {
    const ImportedMaterial& material = geometry.materials[size_t(m)];
    const Vec3 albedo = glm::clamp(material.albedo, 0.0, 1.0);
    if (albedo != material.albedo) report.count("albedo_clamped_to_0_1");
    Material out = material.surface;
    out.albedo = albedo;
    materials[name] = protocol::materialToJson(out);
  }
  warnCoplanar(coplanar, polygons, afterIndex, objectIds, report);
  warnNonManifold(groups, isLight, objectIds, report);
  if (studio && objects.empty())
    throw ValidationError("(import)", "no faces with area are left (every face of the file is degenerate, "
                                      "thinner than 1e-6 of the studio's size, or a duplicate)");
  if (studio) {
    lights.push_back(studioLight(lightIds.take("studio_light"), options.lightRadiance.value_or(Vec3(kStudioRadiance))));
    const std::string material = materialNames.take("studio_white");
    materials[material] = protocol::materialToJson(Material{material, Vec3(0.8)});
    for (Json& quad : studioRoom("studio_", material)) {
      quad["id"] = objectIdPool.take(quad["id"].get<std::string>());
      objects.push_back(std::move(quad));
      report.faces += 1;
    }
    report.studio = StudioFacts{place.scale, place.offset(), studioSentence(report.source, *studio)};
  }
  if (lights.empty())
    throw ValidationError("(import)",
                          "no emissive faces: give a material Ke (or Ka on a material named like a light), "
                          "an emissiveFactor, or use --light-radiance with a material named like a light "
                          "(without --no-studio, or studio=0 over HTTP, such a file goes into the default studio)");

  Json scene = {{"format", "penumbra.scene"}, {"version", 1}, {"lights", lights}, {"objects", objects}};
  if (report.studio) {
    scene["camera"] = studioCamera(placed);
  } else if (geometry.camera.is_object()) {
    scene["camera"] = scaledCamera(geometry.camera, options.scale);
  }
  if (!materials.empty()) scene["materials"] = materials;
  report.objects = objects.size();
  report.lights = lights.size();
  report.materials = materials.size();
  Scene validated = protocol::sceneFromJson(scene);
  return ImportResult{std::move(scene), std::move(validated), std::move(report)};
}

}  // namespace penumbra::interchange
