#include "core/gi/sensor_gi.h"

#include <chrono>
#include <mutex>
#include <stdexcept>
#include <string>

#include "core/gi/id_filter.h"
#include "core/gi/sensor.h"
#include "core/raycast/mesh_lookup.h"

namespace penumbra::gi {

namespace {

constexpr size_t kVerticesPerBeat = 64;

void check(const GiSettings& s) {
  if (s.bounces < 1 || s.bounces > GiSettings::kMaxBounces)
    throw std::invalid_argument("gi: bounces must be 1.." + std::to_string(GiSettings::kMaxBounces));
  if (s.filterRadius < 0 || s.filterRadius > 16 || !(s.filterSigma > 0))
    throw std::invalid_argument("gi: filter radius must be 0..16 and sigma positive");
  if (s.placement.tile < 1 || s.placement.tile > 256 || !(s.placement.threshold >= 0))
    throw std::invalid_argument("gi: tile must be 1..256 and threshold >= 0");
  SensorMap(s.sensorSize);  // throws for a size out of range
  SensorMap(s.vertexSensorSize);
}

// The mesh's irradiance with `extra` (same shape) added per vertex.
Mesh plus(const Mesh& mesh, const Mesh& extra) {
  Mesh sum = mesh;
  for (size_t r = 0; r < sum.receivers.size(); ++r)
    for (size_t v = 0; v < sum.receivers[r].irradiance.size(); ++v)
      sum.receivers[r].irradiance[v] += extra.receivers[r].irradiance[v];
  return sum;
}

// E(q) of a mesh at a hit point, 0 on faces without a receiver mesh.
std::function<Vec3(uint32_t, const Vec3&)> irradianceOf(const MeshLookup& lookup) {
  return [&lookup](uint32_t faceIndex, const Vec3& q) { return lookup.irradiance(faceIndex, q).value_or(Vec3(0.0)); };
}

double meanRelativeChange(const Mesh& before, const Mesh& after) {
  double sum = 0;
  size_t n = 0;
  for (size_t r = 0; r < after.receivers.size(); ++r)
    for (size_t v = 0; v < after.receivers[r].irradiance.size(); ++v) {
      const Vec3 a = after.receivers[r].irradiance[v], b = before.receivers[r].irradiance[v];
      const double scale = std::max({a.x, a.y, a.z});
      if (scale > 0) sum += std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)}) / scale;
      ++n;
    }
  return n ? sum / double(n) : 0;
}

}  // namespace

Mesh vertexIndirect(const Scene& scene, const RayScene& rays, const Mesh& mesh, int sensorSize, int bounces,
                    const Parallel& parallel, std::vector<double>* change, const std::function<void()>& beat) {
  std::mutex beating;  // beats one at a time, from any thread
  const SensorMap map(sensorSize);
  Mesh indirect = mesh;
  for (ReceiverMesh& r : indirect.receivers) std::fill(r.irradiance.begin(), r.irradiance.end(), Vec3(0.0));
  for (int bounce = 1; bounce <= bounces; ++bounce) {
    const Mesh lit = plus(mesh, indirect);  // what surfaces send: direct + the bounces so far
    const MeshLookup lookup(scene, lit);
    const Sensor sensor(scene, rays, map, diffuseOutgoing(scene, irradianceOf(lookup)));
    Mesh next = indirect;
    parallel.forEach(next.receivers.size(), [&](size_t r) {
      ReceiverMesh& receiver = next.receivers[r];
      for (size_t v = 0; v < receiver.positions.size(); ++v) {
        receiver.irradiance[v] = sensor.irradiance(receiver.positions[v], receiver.normal);
        if (beat && v % kVerticesPerBeat == kVerticesPerBeat - 1) {
          std::lock_guard lock(beating);
          beat();
        }
      }
    });
    if (change && bounce > 1) change->push_back(meanRelativeChange(indirect, next));
    indirect = std::move(next);
  }
  return indirect;
}

IndirectImage indirectImage(const Scene& scene, const RayScene& rays, const Mesh& mesh, const GBuffer& gbuffer,
                            const GiSettings& settings, const Parallel& parallel,
                            const std::function<void(size_t sensors)>& progress) {
  check(settings);
  const auto start = std::chrono::steady_clock::now();
  IndirectImage out;
  // Light that surfaces send towards the view's points: direct, plus bounces − 1 bounces.
  Mesh lit = mesh;
  if (settings.bounces > 1) {
    // Its beats report no sensors yet: they are where a cancel is seen.
    const std::function<void()> beat = progress ? std::function<void()>([&] { progress(0); }) : nullptr;
    lit = plus(mesh, vertexIndirect(scene, rays, mesh, settings.vertexSensorSize, settings.bounces - 1,
                                    parallel, &out.bounceChange, beat));
    out.vertexSensors = mesh.vertexCount() * size_t(settings.bounces - 1);
  }
  const MeshLookup lookup(scene, lit);
  const SensorMap map(settings.sensorSize);
  const Sensor sensor(scene, rays, map, diffuseOutgoing(scene, irradianceOf(lookup)));
  const size_t faces = scene.faces().size();
  auto sense = [&](size_t p) {
    const size_t id = size_t(gbuffer.face[p]);
    return sensor.irradiance(gbuffer.position[p], id < faces ? scene.faces()[id].plane.normal : gbuffer.normal.at(p));
  };
  const std::vector<Vec3> sensed =
      placeSensors(gbuffer.width, gbuffer.height, gbuffer.face, sense, settings.placement, parallel, out.placement, progress);
  out.irradiance = settings.filterRadius > 0 ? idAwareGaussian(gbuffer.width, gbuffer.height, sensed, gbuffer.face,
                                                               settings.filterRadius, settings.filterSigma, parallel)
                                             : sensed;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace penumbra::gi
