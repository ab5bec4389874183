// A journal snapshot's mesh parts (server/stored_parts.h) read back as served: every part's key,
// version, shape version (below the version where a light's radiance changed its values alone)
// and mesh bit for bit; bytes of another format or cut short are refused.
#include "server/stored_parts.h"

#include <gtest/gtest.h>

#include "scenegen/cubes_scene.h"
#include "server/scene_session.h"

namespace penumbra::server {
namespace {

TEST(StoredParts, PartsReadBackWithTheirVersionsAndShapeVersions) {
  const Scene scene = makeCubesScene(CubesSceneOptions{6, 3});
  SceneSession session("s", "cubes", scene);
  Edit move;
  move.op = Edit::Op::Move;
  move.id = "cube_0";
  move.transform = scene.objects()[*scene.findObject("cube_0")].transform;
  move.transform.translate.x += 0.1;
  Edit relight;
  relight.op = Edit::Op::SetLight;
  relight.id = scene.lights().at(0).id;
  relight.radiance = scene.lights().at(0).radiance * 1.5;
  session.apply(Frame{{move}});
  const SceneSnapshot& served = *session.apply(Frame{{relight}}).snapshot;

  const StoredParts stored = decodeStoredParts(encodeStoredParts(served));
  ASSERT_EQ(stored.parts.size(), served.parts.size());
  size_t valuesOnly = 0;
  for (size_t i = 0; i < served.parts.size(); ++i) {
    const MeshPart& a = served.parts[i];
    const MeshPart& b = stored.parts[i];
    EXPECT_EQ(a.key, b.key);
    EXPECT_EQ(a.version, b.version);
    EXPECT_EQ(a.shapeVersion, b.shapeVersion);
    EXPECT_TRUE(a.mesh->positions == b.mesh->positions &&
                a.mesh->irradiance == b.mesh->irradiance && a.mesh->classes == b.mesh->classes &&
                a.mesh->triangles == b.mesh->triangles);
    valuesOnly += a.version == served.version && a.shapeVersion < a.version;
  }
  EXPECT_GT(valuesOnly, 0u);  // the radiance changed values alone

  std::string bytes = encodeStoredParts(served);
  std::string otherFormat = bytes;
  otherFormat[7] = '9';
  EXPECT_THROW(decodeStoredParts(otherFormat), std::runtime_error);
  EXPECT_THROW(decodeStoredParts(bytes.substr(0, bytes.size() / 2)), std::runtime_error);
}

}  // namespace
}  // namespace penumbra::server
