// Volumes of a served scene (docs/API.md "Volumes"): POST .../volumes uploads a NRRD file, keeps
// it in the journal (every node finds it: docs/SERVER.md "Volumes on many nodes") and adds it as
// a volume object through the edit queue (one frame, journaled, a version), and
// GET .../volumes/{vid}/preview gives a coarse sketch of its isosurface for the page.
#include <httplib.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <random>

#include "core/engine/volume_edits.h"
#include "core/geom/resource_limit.h"
#include "core/volume/surface_points.h"
#include "protocol/edits_json.h"
#include "protocol/nrrd_volume.h"
#include "protocol/scene_json.h"
#include "server/api_errors.h"
#include "server/body_reader.h"
#include "server/data_directory.h"
#include "server/http_server.h"
#include "server/request_io.h"
#include "server/response_json.h"

namespace penumbra::server {

using nlohmann::json;

namespace {

// The uploaded bytes and the name the client gave them: a raw body or a form's part "file".
struct VolumeUpload {
  std::string bytes;
  std::string fileName;
};

VolumeUpload volumeUploadOf(const httplib::Request& req) {
  VolumeUpload upload;
  if (req.is_multipart_form_data()) {
    for (const auto& [part, value] : req.files)
      if (part != "file")
        throw ApiError(400, error_code::kBadRequest, "(form)." + part,
                       "unknown form part '" + part + "': send one part 'file' (the NRRD)");
    if (req.files.count("file") != 1)
      throw ApiError(400, error_code::kBadRequest, "(form).file",
                     "the form needs exactly one part 'file' (the NRRD)");
    const httplib::MultipartFormData file = req.get_file_value("file");
    upload.bytes = file.content;
    upload.fileName = file.filename;
  } else {
    upload.bytes = req.body;
    upload.fileName = queryText(req, "name").value_or("");  // the file's name, for its id
  }
  if (upload.bytes.empty())
    throw ApiError(400, error_code::kBadRequest,
                   req.is_multipart_form_data() ? "(form).file" : "(body)",
                   "the uploaded volume file is empty");
  return upload;
}

// "CT head.nrrd" → "CT_head"; empty when nothing usable is left.
std::string idFromFileName(const std::string& fileName) {
  std::string id;
  for (char c : std::filesystem::path(fileName).stem().string())
    id += std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ? c : '_';
  return id.substr(0, kMaxIdLength);
}

// A free id: the query's as given (taken → 400), else from the file name, numbered when taken.
std::string volumeIdFor(const httplib::Request& req, const VolumeUpload& upload,
                        const Scene& scene) {
  auto taken = [&](const std::string& id) { return scene.findObject(id) || scene.findVolume(id); };
  if (const auto id = queryText(req, "id")) {
    if (id->empty() || id->size() > kMaxIdLength)
      throw ApiError(400, error_code::kBadParameter, "query.id",
                     "a volume id is 1-" + std::to_string(kMaxIdLength) + " characters");
    if (taken(*id))
      throw ApiError(400, error_code::kBadParameter, "query.id",
                     "duplicate object id '" + *id + "'");
    return *id;
  }
  std::string base = idFromFileName(upload.fileName);
  if (base.empty()) base = "volume";
  std::string id = base;
  for (int n = 2; taken(id); ++n) id = base + "-" + std::to_string(n);
  return id;
}

// A fresh file name for an upload to scene `sceneId`: ID-<16 hex digits>.nrrd.
std::string uploadFileName(const std::string& sceneId) {
  static std::mt19937_64 random{std::random_device{}()};
  static std::mutex randomMutex;
  uint64_t name = 0;
  {
    std::lock_guard lock(randomMutex);
    name = random();
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", (unsigned long long)name);
  return sceneId + "-" + hex + ".nrrd";
}

ApiError notKept(const std::exception& error) {
  return ApiError(503, error_code::kJournalFailed, "",
                  std::string("cannot keep the uploaded volume: ") + error.what() +
                      "; nothing was acknowledged");
}

// The uploaded file read as a volume: 422 naming the body for what the scene loader refuses.
std::shared_ptr<const volume::ScalarVolume> readUpload(const std::string& path,
                                                       const std::string& where) {
  try {
    return protocol::readNrrdVolume(path);
  } catch (const protocol::NrrdError& error) {
    throw ApiError(422, error_code::kInvalidScene, where, error.what());
  } catch (const ResourceLimitError& error) {
    throw ApiError(422, error_code::kInvalidScene, where,
                   std::string(error.what()) + " (a volume's header is checked before its data)");
  } catch (const std::bad_alloc&) {
    throw ApiError(507, error_code::kOutOfMemory, where, "not enough memory for the volume");
  }
}

// The add_volume edit the upload asks for; 400 naming the query parameter it breaks.
Edit addVolumeEdit(const httplib::Request& req, const Scene& scene, VolumeObject volume) {
  if (const auto isovalue = queryNumber(req, "isovalue"))
    volume.isovalue = *isovalue;
  else
    volume.isovalue = 0.5 * (volume.data->minValue() + volume.data->maxValue());
  if (const auto material = queryText(req, "material")) volume.material = *material;
  if (const auto translate = queryVec3(req, "translate")) {
    for (int c = 0; c < 3; ++c)
      if (!(std::abs((*translate)[c]) <= protocol::kMaxCoordinate))
        throw ApiError(400, error_code::kBadParameter, "query.translate",
                       "translate coordinates must be within ±1e9 (the scene format's limit)");
    volume.transform.translate = *translate;
  }
  Edit edit;
  edit.op = Edit::Op::AddVolume;
  edit.id = volume.id;
  edit.volume = std::move(volume);
  try {
    VolumeEditCheck(scene).check(
        edit, 0, [&](const std::string& id) { return scene.findObject(id).has_value(); });
  } catch (const EditError& error) {
    const std::string key = error.path().rfind("volume.", 0) == 0 ? error.path().substr(7) : "id";
    throw ApiError(400, error_code::kBadParameter,
                   "query." + (key == "transform" ? "translate" : key), error.problem());
  }
  return edit;
}

}  // namespace

std::string HttpServer::volumeUploadDir() {
  std::lock_guard lock(uploadDirMutex_);
  if (uploadDir_.empty()) {
    std::filesystem::path dir = options_.dataDir.empty()
                                    ? std::filesystem::temp_directory_path() /
                                          ("penumbra-volumes-" + std::to_string(::getpid()) + "-" +
                                           std::to_string(reinterpret_cast<uintptr_t>(this)))
                                    : std::filesystem::path(options_.dataDir) / "volumes";
    std::filesystem::create_directories(dir);
    uploadDir_ = std::filesystem::absolute(dir).lexically_normal().string();
  }
  return uploadDir_;
}

// Whether `name` is one of storeUpload's files for scene `sceneId` (ID-<16 hex digits>.nrrd).
static bool isUploadOf(const std::string& name, const std::string& sceneId) {
  const size_t hexAt = sceneId.size() + 1;
  if (name.size() != hexAt + 16 + 5 || name.compare(0, hexAt, sceneId + "-") != 0 ||
      name.compare(hexAt + 16, 5, ".nrrd") != 0)
    return false;
  return std::all_of(name.begin() + long(hexAt), name.begin() + long(hexAt + 16),
                     [](char c) { return std::isxdigit(static_cast<unsigned char>(c)); });
}

void HttpServer::removeUploadsOf(const std::string& sceneId) {
  std::error_code error;
  std::string dir;
  {
    std::lock_guard lock(uploadDirMutex_);
    dir = uploadDir_;
  }
  if (dir.empty() && !options_.dataDir.empty())
    dir = (std::filesystem::path(options_.dataDir) / "volumes").string();
  if (dir.empty()) return;  // no upload was ever stored
  for (const auto& entry : std::filesystem::directory_iterator(dir, error))
    if (isUploadOf(entry.path().filename().string(), sceneId))
      std::filesystem::remove(entry.path(), error);
}

HttpServer::KeptUpload HttpServer::keepUpload(SceneSession& session, const std::string& bytes) {
  KeptUpload kept;
  const std::string file = uploadFileName(session.id());
  if (!journal_) {  // ephemeral: a file of this run
    kept.path = (std::filesystem::path(volumeUploadDir()) / file).string();
    try {
      writeFileDurably(kept.path, bytes);
    } catch (const std::exception& error) {
      throw notKept(error);
    }
    return kept;
  }
  kept.key = journalKeyOf(session);
  kept.name = "volumes/" + file;
  kept.path = (std::filesystem::path(journal_->directory()) / kept.name).string();
  try {
    journal_->addVolume(*kept.key, kept.name, bytes);
  } catch (const LeaseLost& error) {
    dropScene(session.id(), error.what());
    throw ApiError(503, error_code::kOwnedElsewhere, "id",
                   std::string(error.what()) + "; the volume was not added, retry");
  } catch (const std::exception& error) {
    throw notKept(error);
  }
  return kept;
}

void HttpServer::discardUpload(const KeptUpload& upload) {
  std::error_code ignored;
  if (!upload.key) {
    std::filesystem::remove(upload.path, ignored);
    return;
  }
  try {
    journal_->removeVolume(*upload.key, upload.name);
  } catch (const std::exception&) {  // kept, unnamed, until the scene is deleted
  }
}

void HttpServer::registerVolumeRoutes() {
  httplib::Server& http = *http_;
  const std::string scenePath = std::string("/api/scenes/") + kIdPattern;

  http.Post(
      scenePath + "/volumes",
      readingBody(options_.maxBodyBytes,
                  guarded([this](const httplib::Request& req, httplib::Response& res) {
                    const auto session = findScene(req.matches[1]);
                    refuseIfStalled(*session);  // nothing stored for a scene that takes no edits
                    refuseIfNotDurable();       // nor where the journal could not name it
                    const VolumeUpload upload = volumeUploadOf(req);
                    const std::shared_ptr<const SceneSnapshot> snapshot = session->snapshot();
                    VolumeObject volume;
                    volume.id = volumeIdFor(req, upload, snapshot->scene);
                    const KeptUpload stored = keepUpload(*session, upload.bytes);
                    volume.file = stored.path;
                    bool kept = false;
                    try {
                      volume.data = readUpload(
                          volume.file, req.is_multipart_form_data() ? "(form).file" : "(body)");
                      Frame frame;
                      frame.edits.push_back(addVolumeEdit(req, snapshot->scene, std::move(volume)));
                      const VolumeObject& added = frame.edits[0].volume;
                      const json info = volumeInfoJson(added);
                      const std::string journaled = journaledFrameText(frame);
                      submitFrame(*session, std::move(frame), journaled, req, res);
                      kept = res.status == 200;
                      if (kept) {
                        json body = json::parse(res.body);
                        body["volume"] = info;
                        sendJson(res, 201, body);
                      }
                    } catch (...) {
                      discardUpload(stored);
                      throw;
                    }
                    if (!kept) discardUpload(stored);
                  })));

  http.Get(scenePath + "/volumes/" + kIdPattern + "/preview",
           guarded([this](const httplib::Request& req, httplib::Response& res) {
             const auto snapshot = findScene(req.matches[1])->snapshot();
             const std::string id = req.matches[2];
             const auto index = snapshot->scene.findVolume(id);
             if (!index)
               throw ApiError(404, error_code::kNotFound, "id", "no volume with id '" + id + "'");
             const VolumeObject& volume = snapshot->scene.volumes()[*index];
             double isovalue = volume.isovalue;
             if (const auto asked = queryNumber(req, "isovalue")) {
               if (const auto problem = isovalueProblem(*volume.data, *asked))
                 throw ApiError(400, error_code::kBadParameter, "query.isovalue", *problem);
               isovalue = *asked;
             }
             const int cells = int(queryUnsigned(req, "cells", 4, 128).value_or(48));
             const volume::SurfacePoints sketch =
                 volume::surfacePoints(*volume.data, isovalue, cells);
             json points = json::array(), normals = json::array();
             for (size_t i = 0; i < sketch.points.size(); ++i)
               for (int a = 0; a < 3; ++a) {
                 points.push_back(float(sketch.points[i][a]));
                 normals.push_back(float(sketch.normals[i][a]));
               }
             sendJson(res, 200,
                      {{"id", id},
                       {"version", snapshot->version},
                       {"isovalue", isovalue},
                       {"stride", sketch.stride},
                       {"points", std::move(points)},
                       {"normals", std::move(normals)}});
           }));
}

}  // namespace penumbra::server
