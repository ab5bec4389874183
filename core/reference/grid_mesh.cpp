#include "core/reference/grid_mesh.h"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/reference/exact_irradiance.h"

namespace penumbra {

namespace {

// Fan-triangulates a convex face from its first corner and splits every fan
// triangle (A, B, C) into N² triangles. Grid point (i, j) of a fan triangle has
// barycentric weights ((N-i-j)/N, i/N, j/N); the edge A–B of one fan triangle
// (j = 0) is the edge A–C (i = 0) of the previous one, so those points are shared.
void gridFace(const Face& face, int n, ReceiverMesh& out) {
  const Polygon3& poly = face.polygon;
  const size_t fans = poly.size() - 2;
  const auto at = [n](int i, int j) { return size_t(j) * size_t(n + 1) + size_t(i); };
  std::vector<uint32_t> previous, current((n + 1) * (n + 1));
  for (size_t t = 0; t < fans; ++t) {
    const Vec3 a = poly[0], b = poly[t + 1], c = poly[t + 2];
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i + j <= n; ++i) {
        if (t > 0 && j == 0) {
          current[at(i, 0)] = previous[at(0, i)];  // shared diagonal A–B
          continue;
        }
        current[at(i, j)] = uint32_t(out.positions.size());
        // Barycentric weights: the face's corners come out exactly.
        const double wb = double(i) / n, wc = double(j) / n, wa = double(n - i - j) / n;
        out.positions.push_back(wa * a + wb * b + wc * c);
      }
    }
    // Both kinds of small triangle keep the fan triangle's (CCW) orientation.
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i + j < n; ++i) {
        out.triangles.push_back({current[at(i, j)], current[at(i + 1, j)], current[at(i, j + 1)]});
        if (i + j + 1 < n)
          out.triangles.push_back(
              {current[at(i + 1, j)], current[at(i + 1, j + 1)], current[at(i, j + 1)]});
      }
    }
    previous.swap(current);
    current.assign((n + 1) * (n + 1), 0);
  }
}

}  // namespace

Mesh referenceGridMesh(const Scene& scene, int gridSize, const ProgressCallback& progress) {
  const int n = std::max(1, gridSize);
  Mesh mesh;
  for (const Face& face : scene.faces()) {
    if (!scene.receivesLight(face)) continue;
    ReceiverMesh receiver;
    receiver.face = face.id;
    receiver.normal = face.plane.normal;
    gridFace(face, n, receiver);
    receiver.irradiance.assign(receiver.positions.size(), Vec3{0.0});
    receiver.classes.assign(receiver.positions.size(), LightClass::Lit);
    mesh.receivers.push_back(std::move(receiver));
  }

  size_t total = 0;
  for (const ReceiverMesh& r : mesh.receivers) total += r.positions.size();
  if (progress) progress(0, total);

  // Faces one at a time (progress from this thread), points in parallel.
  const ExactReference reference(scene);
  size_t done = 0;
  for (ReceiverMesh& r : mesh.receivers) {
    const auto face = std::lower_bound(scene.faces().begin(), scene.faces().end(), r.face,
                                       [](const Face& f, FaceId id) { return f.id < id; });
    tbb::parallel_for(tbb::blocked_range<size_t>(0, r.positions.size(), 16),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t k = range.begin(); k != range.end(); ++k) {
                          const PointIrradiance e =
                              reference.evaluate(r.positions[k], r.normal, shadingNormal(*face, r.positions[k]));
                          r.irradiance[k] = e.irradiance;
                          r.classes[k] = e.lightClass;
                        }
                      });
    done += r.positions.size();
    if (progress) progress(done, total);
  }
  return mesh;
}

}  // namespace penumbra
