// GET /api/scenes/{id}/mesh: the lit mesh whole or since a version, as JSON, binary or GLB.
#include "server/http_server.h"

#include <httplib.h>

#include "interchange/glb_export.h"
#include "server/gzip_encoding.h"
#include "server/mesh_binary.h"
#include "server/request_io.h"

namespace penumbra::server {

using nlohmann::json;

void HttpServer::registerMeshRoutes() {
  httplib::Server& http = *http_;
  const std::string scenePath = std::string("/api/scenes/") + kIdPattern;

  http.Get(
      scenePath + "/mesh", guarded([this](const httplib::Request& req, httplib::Response& res) {
        const auto snapshot = findScene(req.matches[1])->snapshot();
        const auto since = queryUnsigned(req, "since", 0, snapshot->version);
        const std::string format = queryText(req, "format").value_or("json");
        const MeshSelection selection = snapshot->select(since);
        res.set_header("X-Penumbra-Version", std::to_string(snapshot->version));
        if (format == "json") {
          sendJson(res, 200, snapshot->meshJson(selection));
        } else if (format == "bin") {
          res.status = 200;
          res.set_header("Cache-Control", "no-store");
          std::string bytes = mesh_binary::encode(*snapshot, selection);
          // Typed arrays are not a type httplib compresses itself; gzip them when the
          // client takes it (browsers' fetch decodes it transparently).
          res.set_header("Vary", "Accept-Encoding");
          res.set_header("X-Penumbra-Uncompressed-Bytes", std::to_string(bytes.size()));
          const auto policy = options_.meshCompression;
          const bool loopback = req.remote_addr == "127.0.0.1" || req.remote_addr == "::1" ||
                                req.remote_addr.rfind("::ffff:127.", 0) == 0;
          if (policy != ServerOptions::MeshCompression::Never &&
              (policy == ServerOptions::MeshCompression::Always || !loopback) &&
              acceptsGzip(req.get_header_value("Accept-Encoding"))) {
            bytes = gzipCompress(bytes);
            res.set_header("Content-Encoding", "gzip");
          }
          res.set_content(bytes, "application/octet-stream");
        } else if (format == "glb") {
          // The whole scene's lit mesh (a viewer's file, not a delta): `since` is refused.
          if (since)
            throw ApiError(400, error_code::kBadParameter, "query.since",
                           "format=glb is always the whole mesh; drop since");
          // A fixed color_scale keeps colours comparable across versions (the default, 1 /
          // the brightest radiance channel, follows the scene).
          interchange::GlbOptions glbOptions;
          if (const auto scale = queryNumber(req, "color_scale")) {
            if (!(*scale > 0))
              throw ApiError(400, error_code::kBadParameter, "query.color_scale",
                             "color_scale must be positive");
            glbOptions.colorScale = *scale;
          }
          const interchange::GlbFile glb =
              interchange::meshToGlb(snapshot->scene, snapshot->mesh(), glbOptions);
          res.status = 200;
          res.set_header("Cache-Control", "no-store");
          res.set_header("X-Penumbra-Color-Scale", json(glb.colorScale).dump());
          res.set_header("Content-Disposition", "inline; filename=\"" + snapshot->id + ".glb\"");
          res.set_content(std::string(glb.bytes.begin(), glb.bytes.end()), "model/gltf-binary");
        } else {
          throw ApiError(400, error_code::kBadParameter, "query.format",
                         "format must be 'json', 'bin' or 'glb', got '" + format + "'");
        }
      }));
}

}  // namespace penumbra::server
