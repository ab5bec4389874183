// GET /api/scenes/{id}/image: the server's render of a scene version for a camera.
#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <thread>
#include <vector>

#include "core/render/renderer.h"
#include "core/scene/camera_limits.h"
#include "imageio/image_encoding.h"
#include "server/body_reader.h"
#include "server/http_server.h"
#include "server/limits.h"
#include "server/request_io.h"
#include "server/response_json.h"
#include "server/scene_occluders.h"

namespace penumbra::server {

using nlohmann::json;

namespace {

// The query parameter to blame for a camera refused at `cameraKey` (CameraError::key()): its own
// when the query set it, else one the check relates it to (far > near, target ≠ position, up
// against the view direction) that the query set; null when the scene's own camera is at fault.
const char* queryKeyFor(const httplib::Request& req, const std::string& cameraKey) {
  const std::map<std::string, std::vector<const char*>> candidates = {
      {"near", {"near", "far"}},
      {"far", {"far", "near"}},
      {"position", {"position"}},
      {"target", {"target", "position"}},
      {"up", {"up", "position", "target"}},
      {"fov_y_deg", {"fov_y_deg"}},
      {"height", {"ortho_height", "projection"}}};
  const auto it = candidates.find(cameraKey);
  if (it == candidates.end()) return nullptr;
  for (const char* key : it->second)
    if (req.has_param(key)) return key;
  if (cameraKey == "fov_y_deg" && req.has_param("projection")) return "projection";
  return nullptr;
}

// The camera of an image request: the scene's camera (or the default one) with any of the
// query's camera parameters replacing its fields, then core's validateCamera (the scene loader's
// and the renderer's check): 400 naming `query.<name>`, or `camera.<key>` when the field at
// fault is the scene's own.
Camera cameraFromQuery(const httplib::Request& req, const Scene& scene) {
  Camera camera = scene.camera().value_or(defaultCamera(scene.bounds()));
  if (auto v = queryVec3(req, "position")) camera.position = *v;
  if (auto v = queryVec3(req, "target")) camera.target = *v;
  if (auto v = queryVec3(req, "up")) camera.up = *v;
  if (auto p = queryText(req, "projection")) {
    if (*p == "perspective")
      camera.projection = Camera::Projection::Perspective;
    else if (*p == "orthographic")
      camera.projection = Camera::Projection::Orthographic;
    else
      throw ApiError(400, error_code::kBadParameter, "query.projection",
                     "projection must be 'perspective' or 'orthographic', got '" + *p + "'");
  }
  if (auto v = queryNumber(req, "fov_y_deg")) camera.fovYDeg = *v;
  // (`height` is the image's; the orthographic view's height is `ortho_height`.)
  if (auto v = queryNumber(req, "ortho_height")) camera.height = *v;
  if (auto v = queryNumber(req, "near")) camera.near = *v;
  if (auto v = queryNumber(req, "far")) camera.far = *v;
  try {
    validateCamera(camera, scene.bounds());
  } catch (const CameraError& error) {
    if (const char* key = queryKeyFor(req, error.key()))
      throw ApiError(400, error_code::kBadParameter, std::string("query.") + key, error.problem());
    throw ApiError(400, error_code::kBadParameter, "camera." + error.key(),
                   error.problem() + " (the scene's own camera: override it in the query)");
  }
  return camera;
}

// Microfacet paths per pixel: `samples`, else the default as far as the budget allows. Bounded:
// samples × pixels ≤ kMaxImageSampleBudget, so one request's work is bounded whatever it asks.
uint64_t samplesFromQuery(const httplib::Request& req, uint64_t pixels) {
  const uint64_t most = std::max<uint64_t>(1, kMaxImageSampleBudget / pixels);
  const auto samples = queryUnsigned(req, "samples", 1, kMaxImageSamples);
  if (!samples) return std::min(kDefaultImageSamples, most);
  if (*samples > most)
    throw ApiError(400, error_code::kBadParameter, "query.samples",
                   "samples × width × height must be at most " +
                       std::to_string(kMaxImageSampleBudget) +
                       ": at this size samples can be at most " + std::to_string(most) + ", got " +
                       std::to_string(*samples));
  return *samples;
}

// Bounced light by sensors (`gi=sensors`, README "Global illumination"): its settings from the
// query, every value checked; work bounded by pixels × sensor_size² ≤ kMaxGiRayBudget (the rays
// if every pixel got a sensor).
std::optional<gi::GiSettings> giFromQuery(const httplib::Request& req, uint64_t pixels) {
  const auto mode = queryText(req, "gi");
  if (!mode || *mode == "none") {
    for (const char* key : {"sensor_size", "tile", "threshold", "bounces", "filter"})
      if (req.has_param(key))
        throw ApiError(400, error_code::kBadParameter, std::string("query.") + key,
                       std::string(key) + " needs gi=sensors");
    return std::nullopt;
  }
  if (*mode != "sensors")
    throw ApiError(400, error_code::kBadParameter, "query.gi",
                   "gi must be 'sensors' or 'none', got '" + *mode + "'");
  gi::GiSettings gi;
  gi.sensorSize =
      int(queryUnsigned(req, "sensor_size", 1, kMaxGiSensorSize).value_or(gi.sensorSize));
  if (pixels * uint64_t(gi.sensorSize) * uint64_t(gi.sensorSize) > kMaxGiRayBudget)
    throw ApiError(400, error_code::kBadParameter, "query.sensor_size",
                   "width × height × sensor_size² must be at most " +
                       std::to_string(kMaxGiRayBudget) + ": use a smaller image or sensor");
  gi.placement.tile = int(queryUnsigned(req, "tile", 1, 256).value_or(gi.placement.tile));
  gi.bounces = int(queryUnsigned(req, "bounces", 1, kMaxGiBounces).value_or(gi.bounces));
  gi.filterRadius = int(queryUnsigned(req, "filter", 0, 16).value_or(gi.filterRadius));
  if (const auto threshold = queryNumber(req, "threshold")) {
    if (!(*threshold >= 0 && *threshold <= 10))
      throw ApiError(400, error_code::kBadParameter, "query.threshold",
                     "threshold must be in [0, 10]");
    gi.placement.threshold = *threshold;
  }
  return gi;
}

// The query's `ticket` (the client's own name for this render, to poll or cancel it) or `page`
// (its page's, so a newer render stops the older), checked; empty when not given.
std::string renderLabel(const httplib::Request& req, const char* key) {
  const std::string label = queryText(req, key).value_or("");
  if (label.size() > kMaxIdLength ||
      label.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") !=
          std::string::npos)
    throw ApiError(400, error_code::kBadParameter, std::string("query.") + key,
                   std::string(key) + " must be up to " + std::to_string(kMaxIdLength) +
                       " letters, digits, '_' or '-'");
  return label;
}

// The query's `seq`: the render's number among its page's (counting up), which orders them.
std::optional<uint64_t> renderSeq(const httplib::Request& req, const std::string& page) {
  const auto seq = queryUnsigned(req, "seq", 0, kMaxRenderSeq);
  if (seq && page.empty())
    throw ApiError(400, error_code::kBadParameter, "query.seq",
                   "seq numbers a page's renders: give the page too");
  return seq;
}

}  // namespace

// The image's estimated working memory from the budget, or nullopt when others hold it now;
// 400 when the image alone needs more than the whole budget.
std::optional<WorkBudget::Share> HttpServer::takeImageMemory(uint64_t pixels, bool gi) {
  const uint64_t bytes = pixels * (gi ? kGiImageBytesPerPixel : kImageBytesPerPixel);
  if (!imageBudget_.fits(bytes))
    throw ApiError(400, error_code::kBadParameter, "query.width",
                   "this image needs about " + std::to_string(bytes >> 20) +
                       " MiB of working memory, more than the server's " +
                       std::to_string(imageBudget_.capacity() >> 20) +
                       " MiB for images (serve --image-memory-mib): ask for fewer pixels" +
                       (gi ? " (sensor GI takes 4× the memory a pixel)" : ""));
  return imageBudget_.tryTake(bytes);
}

void HttpServer::registerImageRoutes() {
  httplib::Server& http = *http_;
  const std::string scenePath = std::string("/api/scenes/") + kIdPattern;

  http.Get(scenePath + "/image",
           guarded([this](const httplib::Request& req, httplib::Response& res) {
             const auto snapshot = findScene(req.matches[1])->snapshot();
             const auto width = queryUnsigned(req, "width", 1, kMaxImageSide);
             const auto height = queryUnsigned(req, "height", 1, kMaxImageSide);
             if (!width)
               throw ApiError(400, error_code::kBadParameter, "query.width",
                              "width is required (1 to " + std::to_string(kMaxImageSide) + ")");
             if (!height)
               throw ApiError(400, error_code::kBadParameter, "query.height",
                              "height is required (1 to " + std::to_string(kMaxImageSide) + ")");
             const std::string format = queryText(req, "format").value_or("png");
             if (format != "png" && format != "exr")
               throw ApiError(400, error_code::kBadParameter, "query.format",
                              "format must be 'png' or 'exr', got '" + format + "'");
             RenderSettings settings;
             settings.width = int(*width);
             settings.height = int(*height);
             settings.camera = cameraFromQuery(req, snapshot->scene);
             // Progressive passes ask for few samples first (README "The page"): paths per pixel,
             // and stratified samples per light (split over its visible pieces) from 4 up to the
             // CLI's 16.
             const uint64_t samples = samplesFromQuery(req, *width * *height);
             settings.microfacet.pathsPerPixel = int(samples);
             settings.microfacet.lightSamples = int(std::clamp<uint64_t>(samples, 4, 16));
             // The DM's exact visibility from the snapshot's frozen occluder lists: no engine, no
             // lock.
             settings.occluders = occluderLookup(snapshot->occluders);
             settings.gi = giFromQuery(req, *width * *height);
             // A newer view of the same page stops the renders it replaces before it waits for
             // their memory (or, overtaken on its way by a newer one, is refused).
             const std::string page = renderLabel(req, "page");
             const auto seq = renderSeq(req, page);
             renders_.supersede(page, seq);
             const auto share = takeImageMemory(*width * *height, settings.gi.has_value());
             if (!share)
               return sendBusy(res, "the images rendering now hold the server's image memory (" +
                                        std::to_string(imageBudget_.capacity() >> 20) + " MiB)");
             const auto job = renders_.start(req.matches[1], renderLabel(req, "ticket"), page, seq,
                                             ConnectionServer::clientGoneProbe());
             job->setPixels(*width * *height);
             res.set_header("X-Penumbra-Render-Ticket", job->ticket());
             RenderedImage image;
             std::vector<uint8_t> bytes;
             const auto draw = [&] {
               image = render(snapshot->scene, snapshot->mesh(), settings,
                              [&job](size_t done, size_t total) { job->report(done, total); });
               job->stage("encoding");
               bytes = format == "png" ? imageio::encodePng(image) : imageio::encodeExr(image);
             };
             try {
               // A costly image goes to the costly lane (one core each, below edits and reads);
               // a quick one (a page's first passes) draws here on every core.
               if (settings.gi || *width * *height * samples > kQuickImageWork)
                 costlyImages_.run(draw);
               else
                 draw();
             } catch (const RenderCancelled& why) {
               job->end(RenderJob::State::Cancelled);
               throw ApiError(409, error_code::kRenderCancelled, "",
                              std::string("the render was cancelled: ") + why.what());
             } catch (const std::invalid_argument& error) {  // e.g. a degenerate camera
               job->end(RenderJob::State::Failed);
               throw ApiError(400, error_code::kBadParameter, "query", error.what());
             } catch (...) {
               job->end(RenderJob::State::Failed);
               throw;
             }
             job->end(RenderJob::State::Done);
             res.status = 200;
             res.set_header("Cache-Control", "no-store");
             res.set_header("X-Penumbra-Version", std::to_string(snapshot->version));
             setMeshToleranceHeader(res, options_.engine.meshTolerance);
             res.set_header("X-Penumbra-Render-Seconds", std::to_string(image.seconds));
             res.set_header("X-Penumbra-Samples", std::to_string(samples));
             if (image.gi) {
               res.set_header("X-Penumbra-Gi-Sensors", std::to_string(image.gi->placement.sensors));
               res.set_header("X-Penumbra-Gi-Seconds", std::to_string(image.gi->seconds));
             }
             res.set_content(std::string(bytes.begin(), bytes.end()),
                             format == "png" ? "image/png" : "image/x-exr");
           }));

  // Renders as jobs (server/render_job.h): listed, polled, cancelled by ticket.
  http.Get(scenePath + "/renders",
           guarded([this](const httplib::Request& req, httplib::Response& res) {
             findScene(req.matches[1]);
             json list = json::array();
             for (const auto& job : renders_.ofScene(req.matches[1])) list.push_back(job->toJson());
             sendJson(res, 200, {{"renders", list}});
           }));
  http.Get(scenePath + "/renders/([A-Za-z0-9_-]+)",
           guarded([this](const httplib::Request& req, httplib::Response& res) {
             sendJson(res, 200, findRender(req.matches[1], req.matches[2])->toJson());
           }));
  http.Delete(scenePath + "/renders/([A-Za-z0-9_-]+)",
              readingBody(options_.maxBodyBytes,
                          guarded([this](const httplib::Request& req, httplib::Response& res) {
                            const auto job = findRender(req.matches[1], req.matches[2]);
                            job->cancel("cancelled by DELETE");
                            // The render stops at its next report: wait for it, boundedly, so the
                            // answer says how it ended.
                            const auto deadline =
                                std::chrono::steady_clock::now() + kRenderCancelWait;
                            while (!job->ended() && std::chrono::steady_clock::now() < deadline)
                              std::this_thread::sleep_for(std::chrono::milliseconds(10));
                            sendJson(res, 200, job->toJson());
                          })));
}

std::shared_ptr<RenderJob> HttpServer::findRender(const std::string& sceneId,
                                                  const std::string& ticket) const {
  auto job = renders_.find(sceneId, ticket);
  if (!job)
    throw ApiError(404, error_code::kNotFound, "ticket",
                   "no render '" + ticket + "' of scene '" + sceneId +
                       "' running or ended in the last " +
                       std::to_string(int(RenderJobs::kKeepEndedSeconds)) + " s");
  return job;
}

}  // namespace penumbra::server
