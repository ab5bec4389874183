#include "interchange/import_report.h"

#include "protocol/utf8.h"

namespace penumbra::interchange {

using protocol::replacingInvalidUtf8;

// Warnings and the source name quote the file's own bytes, which need not be UTF-8.
nlohmann::json ImportReport::toJson() const {
  nlohmann::json validWarnings = nlohmann::json::array();
  for (const std::string& warning : warnings) validWarnings.push_back(replacingInvalidUtf8(warning));
  nlohmann::json meshJson = nlohmann::json::array();
  for (const ObjectMeshFacts& mesh : meshes)
    meshJson.push_back({{"object", mesh.object},
                        {"faces", mesh.faces},
                        {"vertices_welded", mesh.verticesWelded},
                        {"components", mesh.components},
                        {"closed_components", mesh.closedComponents},
                        {"faces_flipped", mesh.facesFlipped},
                        {"non_manifold_edges", mesh.nonManifoldEdges},
                        {"boundary_edges", mesh.boundaryEdges}});
  nlohmann::json out = {{"source", replacingInvalidUtf8(source)},
                        {"format", format},
                        {"objects", objects},
                        {"faces", faces},
                        {"lights", lights},
                        {"materials", materials},
                        {"triangles_read", trianglesRead},
                        {"bounds", {{"min", {boundsMin.x, boundsMin.y, boundsMin.z}},
                                    {"max", {boundsMax.x, boundsMax.y, boundsMax.z}}}},
                        {"repairs", repairs},
                        {"warnings", validWarnings},
                        {"meshes", meshJson}};
  if (studio)
    out["studio"] = {{"scale", studio->scale},
                     {"offset", {studio->offset.x, studio->offset.y, studio->offset.z}},
                     {"sentence", replacingInvalidUtf8(studio->sentence)}};
  return out;
}

namespace {

std::string counted(size_t n, const std::string& word, const std::string& plural) {
  return std::to_string(n) + " " + (n == 1 ? word : plural);
}

}  // namespace

std::string ObjectMeshFacts::sentence() const {
  std::string text = "'" + object + "': " + counted(faces, "face", "faces") + ", " +
                     counted(components, "component", "components") + ", " + std::to_string(closedComponents) +
                     " closed";
  if (facesFlipped) text += "; " + counted(facesFlipped, "face", "faces") + " flipped";
  if (verticesWelded) text += "; " + counted(verticesWelded, "vertex", "vertices") + " welded";
  if (nonManifoldEdges) text += "; " + counted(nonManifoldEdges, "non-manifold edge", "non-manifold edges") + " left";
  return text;
}

std::string ImportReport::summary() const {
  std::string text = source + " (" + format + "): " + std::to_string(objects) + " objects, " +
                     std::to_string(faces) + " faces, " + std::to_string(lights) + " lights, " +
                     std::to_string(materials) + " materials\n";
  if (studio) text += "  " + studio->sentence + "\n";
  for (const ObjectMeshFacts& mesh : meshes) text += "  " + mesh.sentence() + "\n";
  if (repairs.empty()) text += "  no repairs\n";
  for (const auto& [repair, times] : repairs) text += "  repaired: " + repair + " × " + std::to_string(times) + "\n";
  for (const std::string& warning : warnings) text += "  warning: " + warning + "\n";
  return text;
}

}  // namespace penumbra::interchange
