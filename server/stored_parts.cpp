#include "server/stored_parts.h"

#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace penumbra::server {

namespace {

// Format 2 adds each part's shape version; format 1 (before it) reads with shape = version.
constexpr char kMagic[8] = {'P', 'N', 'S', 'P', 'A', 'R', 'T', '2'};
constexpr char kMagicFormat1[8] = {'P', 'N', 'S', 'P', 'A', 'R', 'T', '1'};

// Values are copied as they lie in memory: the journal is read back by the same build on the
// same machine kind (little-endian x86-64 / aarch64), like the rest of its bytes.
class Writer {
 public:
  template <typename T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    out_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  template <typename T>
  void putArray(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(uint64_t(values.size()));
    out_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  void putText(const std::string& text) {
    put(uint64_t(text.size()));
    out_ += text;
  }
  void putKey(const PartKey& key) {
    putText(key.receiver.object);
    put(key.receiver.face);
    put(key.x);
    put(key.y);
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

class Reader {
 public:
  explicit Reader(const std::string& bytes) : in_(bytes) {}
  template <typename T>
  T get() {
    T value;
    std::memcpy(&value, take(sizeof(T)), sizeof(T));
    return value;
  }
  template <typename T>
  std::vector<T> getArray() {
    const uint64_t count = get<uint64_t>();
    if (count > (in_.size() - at_) / sizeof(T)) fail();
    std::vector<T> values(count);
    std::memcpy(values.data(), take(count * sizeof(T)), count * sizeof(T));
    return values;
  }
  std::string getText() {
    const uint64_t size = get<uint64_t>();
    if (size > in_.size() - at_) fail();
    return std::string(take(size), size);
  }
  PartKey getKey() {
    PartKey key;
    key.receiver.object = getText();
    key.receiver.face = get<uint32_t>();
    key.x = get<int64_t>();
    key.y = get<int64_t>();
    return key;
  }
  bool atEnd() const { return at_ == in_.size(); }
  [[noreturn]] static void fail() {
    throw std::runtime_error("the snapshot's mesh parts are truncated or not of this format");
  }

 private:
  const char* take(size_t size) {
    if (size > in_.size() - at_) fail();
    const char* at = in_.data() + at_;
    at_ += size;
    return at;
  }
  const std::string& in_;
  size_t at_ = 0;
};

}  // namespace

std::string encodeStoredParts(const SceneSnapshot& snapshot) {
  Writer out;
  out.bytes().append(kMagic, sizeof(kMagic));
  out.put(uint64_t(snapshot.parts.size()));
  for (const MeshPart& part : snapshot.parts) {
    out.putKey(part.key);
    out.put(part.version);
    out.put(part.shapeVersion);
    const ReceiverMesh& mesh = *part.mesh;
    out.put(mesh.face);
    out.put(mesh.normal);
    out.putArray(mesh.positions);
    out.putArray(mesh.irradiance);
    out.putArray(mesh.classes);
    out.putArray(mesh.triangles);
  }
  out.put(uint64_t(snapshot.removed.size()));
  for (const auto& [key, version] : snapshot.removed) {
    out.putKey(key);
    out.put(version);
  }
  out.put(snapshot.removedFloor);
  std::vector<uint32_t> handles;
  for (size_t o = 0; o < snapshot.scene.objects().size(); ++o)
    handles.push_back(snapshot.scene.handleOf(o));
  out.putArray(handles);
  out.put(snapshot.scene.nextHandle());
  return std::move(out.bytes());
}

StoredParts decodeStoredParts(const std::string& bytes) {
  if (bytes.size() < sizeof(kMagic)) Reader::fail();
  const bool format1 = std::memcmp(bytes.data(), kMagicFormat1, sizeof(kMagic)) == 0;
  if (!format1 && std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) Reader::fail();
  Reader in(bytes);
  for (size_t i = 0; i < sizeof(kMagic); ++i) in.get<char>();
  StoredParts stored;
  const uint64_t parts = in.get<uint64_t>();
  for (uint64_t p = 0; p < parts; ++p) {
    MeshPart part;
    part.key = in.getKey();
    part.version = in.get<uint64_t>();
    part.shapeVersion = format1 ? part.version : in.get<uint64_t>();
    if (part.shapeVersion > part.version) Reader::fail();
    auto mesh = std::make_shared<ReceiverMesh>();
    mesh->face = in.get<FaceId>();
    mesh->normal = in.get<Vec3>();
    mesh->positions = in.getArray<Vec3>();
    mesh->irradiance = in.getArray<Vec3>();
    mesh->classes = in.getArray<LightClass>();
    mesh->triangles = in.getArray<std::array<uint32_t, 3>>();
    part.mesh = std::move(mesh);
    stored.parts.push_back(std::move(part));
  }
  const uint64_t removed = in.get<uint64_t>();
  for (uint64_t r = 0; r < removed; ++r) {
    PartKey key = in.getKey();
    stored.removed.emplace_back(std::move(key), in.get<uint64_t>());
  }
  stored.removedFloor = in.get<uint64_t>();
  stored.handles = in.getArray<uint32_t>();
  stored.nextHandle = in.get<uint32_t>();
  if (!in.atEnd()) Reader::fail();
  return stored;
}

}  // namespace penumbra::server
