// GET /api/scenes/{id}/mesh: the lit mesh whole or since a version, as JSON, binary or GLB, with
// the indirect light baked per vertex when asked (indirect=1, server/indirect_cache.h).
#include "server/http_server.h"

#include <httplib.h>

#include "interchange/glb_export.h"
#include "server/gzip_encoding.h"
#include "server/mesh_binary.h"
#include "server/request_io.h"
#include "server/streamed_answer.h"

namespace penumbra::server {

using nlohmann::json;

namespace {

// `indirect=1` and its settings, every value checked; the work is bounded by
// vertices × sensor_size² × bounces ≤ kMaxIndirectRayBudget.
std::optional<IndirectSettings> indirectFromQuery(const httplib::Request& req, const SceneSnapshot& snapshot,
                                                  bool delta) {
  const auto flag = queryUnsigned(req, "indirect", 0, 1);
  if (!flag || *flag == 0) {
    for (const char* key : {"sensor_size", "bounces"})
      if (req.has_param(key))
        throw ApiError(400, error_code::kBadParameter, std::string("query.") + key,
                       std::string(key) + " needs indirect=1");
    return std::nullopt;
  }
  // Indirect light at a vertex depends on the whole scene: any edit changes it everywhere.
  if (delta)
    throw ApiError(400, error_code::kBadParameter, "query.since",
                   "indirect=1 is always the whole mesh (any edit changes indirect light everywhere); drop since");
  IndirectSettings settings;
  settings.sensorSize = int(queryUnsigned(req, "sensor_size", 1, kMaxGiSensorSize).value_or(settings.sensorSize));
  settings.bounces = int(queryUnsigned(req, "bounces", 1, kMaxGiBounces).value_or(settings.bounces));
  const uint64_t rays = uint64_t(snapshot.vertexCount()) * uint64_t(settings.sensorSize) *
                        uint64_t(settings.sensorSize) * uint64_t(settings.bounces);
  if (rays > kMaxIndirectRayBudget)
    throw ApiError(400, error_code::kBadParameter, "query.sensor_size",
                   "vertices × sensor_size² × bounces must be at most " + std::to_string(kMaxIndirectRayBudget) +
                       " (this version has " + std::to_string(snapshot.vertexCount()) +
                       " vertices): use a smaller sensor_size or fewer bounces");
  return settings;
}

// The mesh JSON answer, streamed, with, per receiver, "indirect": [[r, g, b], ...] and the
// bake's settings. The writer owns the snapshot and bake it reads: it runs after the handler.
void sendMeshJson(httplib::Response& res, std::shared_ptr<const SceneSnapshot> snapshot, MeshSelection selection,
                  std::shared_ptr<const IndirectBake> bake, double tolerance) {
  res.set_header("Cache-Control", "no-store");
  sendStreamed(res, "application/json", [snapshot, selection = std::move(selection), bake, tolerance](std::ostream& out) {
    protocol::MeshJsonExtras indirect;
    indirect.root["tolerance"] = tolerance;
    if (bake) {
      indirect.root["indirect"] = {{"sensor_size", bake->settings.sensorSize}, {"bounces", bake->settings.bounces}};
      indirect.receiver = [&bake](size_t r) {
        json values = json::array();
        for (const Vec3& e : bake->mesh.receivers.at(r).irradiance) values.push_back({e.x, e.y, e.z});
        return json{{"indirect", std::move(values)}};
      };
    }
    snapshot->writeMeshJson(out, selection, indirect);
  });
}

void sendBinary(const httplib::Request& req, httplib::Response& res, std::string bytes,
                ServerOptions::MeshCompression policy) {
  res.status = 200;
  res.set_header("Cache-Control", "no-store");
  // Typed arrays are not a type httplib compresses itself; gzip them when the
  // client takes it (browsers' fetch decodes it transparently).
  res.set_header("Vary", "Accept-Encoding");
  res.set_header("X-Penumbra-Uncompressed-Bytes", std::to_string(bytes.size()));
  const bool loopback = req.remote_addr == "127.0.0.1" || req.remote_addr == "::1" ||
                        req.remote_addr.rfind("::ffff:127.", 0) == 0;
  if (policy != ServerOptions::MeshCompression::Never &&
      (policy == ServerOptions::MeshCompression::Always || !loopback) &&
      acceptsGzip(req.get_header_value("Accept-Encoding"))) {
    bytes = gzipCompress(bytes);
    res.set_header("Content-Encoding", "gzip");
  }
  res.set_content(bytes, "application/octet-stream");
}

void sendGlb(const httplib::Request& req, httplib::Response& res, const SceneSnapshot& snapshot,
             const IndirectBake* bake) {
  // A fixed color_scale keeps colours comparable across versions (the default, the page's
  // automatic exposure, follows the scene).
  interchange::GlbOptions glbOptions;
  if (const auto scale = queryNumber(req, "color_scale")) {
    if (!(*scale > 0))
      throw ApiError(400, error_code::kBadParameter, "query.color_scale", "color_scale must be positive");
    glbOptions.colorScale = *scale;
  }
  if (bake) glbOptions.indirect = &bake->mesh;
  const interchange::GlbFile glb = interchange::meshToGlb(snapshot.scene, snapshot.mesh(), glbOptions);
  res.status = 200;
  res.set_header("Cache-Control", "no-store");
  res.set_header("X-Penumbra-Color-Scale", json(glb.colorScale).dump());
  res.set_header("Content-Disposition", "inline; filename=\"" + snapshot.id + ".glb\"");
  res.set_content(std::string(glb.bytes.begin(), glb.bytes.end()), "model/gltf-binary");
}

}  // namespace

void HttpServer::registerMeshRoutes() {
  httplib::Server& http = *http_;
  const std::string scenePath = std::string("/api/scenes/") + kIdPattern;

  http.Get(
      scenePath + "/mesh", guarded([this](const httplib::Request& req, httplib::Response& res) {
        const auto session = findScene(req.matches[1]);
        const auto snapshot = session->snapshot();
        const auto since = queryUnsigned(req, "since", 0, snapshot->version);
        const std::string format = queryText(req, "format").value_or("json");
        if (format != "json" && format != "bin" && format != "glb")
          throw ApiError(400, error_code::kBadParameter, "query.format",
                         "format must be 'json', 'bin' or 'glb', got '" + format + "'");
        // The whole scene's lit mesh (a viewer's file, not a delta): `since` is refused.
        if (format == "glb" && since)
          throw ApiError(400, error_code::kBadParameter, "query.since",
                         "format=glb is always the whole mesh; drop since");
        const auto indirect = indirectFromQuery(req, *snapshot, since.has_value());
        // Baked from the snapshot alone, outside any engine lock (indirect_cache.h).
        IndirectCache::Found bake;
        if (indirect) bake = session->indirectCache().get(*snapshot, *indirect, options_.engine.threads);
        res.set_header("X-Penumbra-Version", std::to_string(snapshot->version));
        setMeshToleranceHeader(res, options_.engine.meshTolerance);
        if (bake.bake) {
          res.set_header("X-Penumbra-Indirect-Seconds", std::to_string(bake.bake->seconds));
          res.set_header("X-Penumbra-Indirect-Cached", bake.cached ? "1" : "0");
          res.set_header("X-Penumbra-Indirect-Sensor-Size", std::to_string(indirect->sensorSize));
        }
        const MeshSelection selection = snapshot->select(since);
        if (format == "json")
          sendMeshJson(res, snapshot, selection, bake.bake, options_.engine.meshTolerance);
        else if (format == "bin")
          sendBinary(req, res, mesh_binary::encode(*snapshot, selection, bake.bake.get()), options_.meshCompression);
        else
          sendGlb(req, res, *snapshot, bake.bake.get());
      }));
}

}  // namespace penumbra::server
