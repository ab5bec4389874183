// Every view of a scene says which interpolation bound its display mesh meets: the mesh (JSON
// root "tolerance", and the header X-Penumbra-Mesh-Tolerance on every format), the images
// shaded from it and /stats; and the bound said is the one applied (a refined server's mesh
// has more vertices than the fans of an unrefined one).
#include "tests/server/server_fixture.h"

namespace penumbra::server::test {
namespace {

struct Said {
  double jsonRoot = -1, stats = -1;
  std::vector<std::string> headers;  // json, bin, glb, image
  size_t vertices = 0;
};

Said whatItSays(double tolerance) {
  ServerOptions options = RunningServer::loopback();
  options.engine.meshTolerance = tolerance;
  RunningServer running(options);
  const std::string base = "/api/scenes/" + running.addBundled("cornell");
  auto client = running.client();
  Said said;
  const auto mesh = client.Get((base + "/mesh").c_str());
  EXPECT_EQ(mesh->status, 200);
  said.jsonRoot = bodyJson(mesh)["tolerance"].get<double>();
  for (const char* path : {"/mesh", "/mesh?format=bin", "/mesh?format=glb", "/image?width=32&height=24"}) {
    const auto res = client.Get((base + path).c_str());
    EXPECT_EQ(res->status, 200) << path << ": " << res->body;
    said.headers.push_back(res->get_header_value("X-Penumbra-Mesh-Tolerance"));
  }
  const json stats = bodyJson(client.Get((base + "/stats").c_str()));
  said.stats = stats["mesh"]["tolerance"].get<double>();
  said.vertices = stats["mesh"]["vertices"].get<size_t>();
  return said;
}

TEST(MeshTolerance, EveryViewSaysTheBoundItsMeshMeets) {
  const Said fans = whatItSays(0), refined = whatItSays(0.005);
  EXPECT_EQ(fans.jsonRoot, 0);
  EXPECT_EQ(fans.stats, 0);
  for (const std::string& header : fans.headers) EXPECT_EQ(json::parse(header), 0) << header;
  EXPECT_EQ(refined.jsonRoot, 0.005);
  EXPECT_EQ(refined.stats, 0.005);
  for (const std::string& header : refined.headers) EXPECT_EQ(json::parse(header), 0.005) << header;
  // The bound said is the bound applied: refining adds points where interpolation was off.
  EXPECT_GT(refined.vertices, fans.vertices);
}

}  // namespace
}  // namespace penumbra::server::test
