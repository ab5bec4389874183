// `penumbra`: the command-line entry point. Dispatches to one subcommand and turns
// every error into a message on stderr and an exit status (never a crash).
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "protocol/validation_error.h"
#include "cli/commands.h"

namespace {

constexpr const char* kUsage = R"(usage: penumbra COMMAND [ARGS]

commands:
  validate SCENE                       check a scene file (exit 0, or 2 with the key path of the problem)
  info SCENE                           faces, lights, bounds and per-light face classes
  reference SCENE --grid N --out MESH  exact reference irradiance on an N×N grid per receiving face
  build SCENE --out MESH [--stats]     the discontinuity mesh; --stats prints counters and timings as JSON
           [--color-scale S] [--edges] MESH ending in .glb: glTF binary, COLOR_0 = min(1, S × radiance
                                       with the ambient fill; default S: the page's exposure), exact
                                       _RADIANCE and _IRRADIANCE; lights emissive; the camera
           [--indirect [--sensor-size N] [--bounces B]]  .glb: the indirect light instead of the fill (sensors of N², 8)
           [--grid G]                  overlap-cube tiles per side (default: from the face count,
                                       a model casting whole counting as ≤ 1,024)
           [--threads N]               build threads (also replay, serve); default: every core
           [--mesh-tolerance F]        display mesh refined until interpolation is within F of the
                                       local unshadowed light (also render, replay, serve); default
                                       0.005, serve 0; 0: a fan per cell piece
  render SCENE --out IMG.png|IMG.exr   an image shaded by the DM mesh (built, or --mesh MESH);
         [--width W] [--height H]      default 512×512, at most 8192 per side
         [--camera JSON|FILE]          default: the scene's camera, else a view of its bounds
         [--reference] [--stats]       shade with the exact reference; print timings as JSON
         [--gi sensors]                bounced light by sensors (seed 001) instead of ambient:
         [--sensor-size N] [--tile N]  sensor map N×N (32), first tiles (16 px),
         [--threshold F] [--bounces B] corner spread interpolated (0.05), bounces (1..8),
         [--filter R]                  id-aware Gaussian radius in pixels (0: off)
         [--exposure E]                linear scale before the PNG's sRGB (0: automatic)
  import FILE --out SCENE               an OBJ (+MTL), glTF or GLB file as a scene; repairs on stderr
           [--scale S] [--light-radiance R,G,B] [--report REPORT.json]
           [--no-studio]               a file without lights is an error (default: it goes into
                                       a 6×3×6 m studio under a 1 m² light, scaled to fit)
  generate --cubes N --out SCENE       a seeded 'N random cubes in a room' scene
           [--seed S] [--light-scale F] [--stacked-fraction F] [--tilted-light]
           [--two-lights] [--tables FRACTION]
           [--dense]                   N boxes of random size and turn floating in a 6×3×6 m room
  generate --sphere FACES --out SCENE  one UV sphere of ~FACES faces (radius 0.35 m) in that room
  generate --model NAME --out SCENE    a tessellated model in that room: teapot | torus-knot | blob |
           [--triangles N] [--rest]    bowl | scan (~N triangles; 6000, scan 70000), floating or on
           [--seed S]                  the floor; furnished: 9 models and 2 tables (~N = 100000)
           [--smooth]                  models shaded smooth: corner normals across edges under 60°
  generate --volume FIELD --out X.nrrd a test field (marschner-lobb, sphere, smoke, mixing) as
           [--size N] [--type T]       gzip NRRD: N³ voxels (64), uchar | ushort | float (uchar),
           [--spacing S] [--seed S]    voxel spacing (1/(N−1): a 1 m cube), noise seed
  replay SCENE EDITS.jsonl             apply an edit script frame by frame; per-frame times and counts
         [--verify] [--verify-every K] [--report OUT.json] [--out MESH] [--threads N]
         [--display-mesh]              also time the display mesh after each frame (as serve)
  serve [SCENE...] [--host H]          the HTTP API and web page (docs/API.md) on the scenes;
        [--port P] [--static DIR]      default 127.0.0.1:8080 and ./web_client; prints the URL
        [--grid G] [--threads N]
        [--data DIR | --ephemeral]     journal of scenes and edits (default ./penumbra-data)
        [--journal postgresql://...]   keep the journal in that PostgreSQL database instead
                                       (uploaded files stay in the data directory)
        [--node-id ID] [--restore R]   with it, nodes share scenes by leases: this node's name
        [--lease-seconds S]            (default hostname:port), all (default) or on-request
        [--idle-release S]             restores at start, lease length (3 s), idle scenes given
                                       back after S s (600); docs/SERVER.md "Many nodes"
        [--snapshot-every N]           journal a snapshot every N versions of a scene, so a
                                       restart replays at most N frames (default 200; 0: never)
        [--token T] [--max-scenes N]   token for mutating requests (needed off loopback; or
        [--max-body-mib M]             PENUMBRA_TOKEN); limits (default 32 scenes, 16 MiB)
        [--image-memory-mib M]         images rendering at once (default 512 MiB; then 503)
        [--edit-nice K]                edits apply K nice steps below reads (0-19; default 0)
        [--max-frame-work W]           refuse a frame whose light work is past W (422)
        [--max-connections-per-ip N]   connections one client address may hold (default 256)
        [--allow-origin O,...]         other origins whose pages may edit (default: only the
                                       server's own page; a loopback server answers loopback Hosts)
  help                                 this text
)";

int dispatch(int argc, char** argv) {
  using namespace penumbra::cli;
  if (argc < 2 || !std::strcmp(argv[1], "help") || !std::strcmp(argv[1], "--help")) {
    std::fputs(kUsage, argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  if (command == "validate") return runValidate(Args(argc, argv, 2, {}));
  if (command == "info") return runInfo(Args(argc, argv, 2, {}));
  if (command == "reference") return runReference(Args(argc, argv, 2, {}));
  if (command == "build") return runBuild(Args(argc, argv, 2, {"stats", "edges", "indirect"}));
  if (command == "import") return runImport(Args(argc, argv, 2, {"no-studio"}));
  if (command == "render") return runRender(Args(argc, argv, 2, {"reference", "stats"}));
  if (command == "replay") return runReplay(Args(argc, argv, 2, {"verify", "display-mesh"}));
  if (command == "serve") return runServe(Args(argc, argv, 2, {"ephemeral"}));
  if (command == "generate") return runGenerate(Args(argc, argv, 2, {"tilted-light", "two-lights", "dense", "rest", "smooth"}));
  throw UsageError("unknown command '" + command + "'");
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return dispatch(argc, argv);
  } catch (const penumbra::protocol::ValidationError& error) {
    std::fprintf(stderr, "penumbra: invalid input: %s\n", error.what());
    return 2;
  } catch (const penumbra::cli::UsageError& error) {
    std::fprintf(stderr, "penumbra: %s\n(run 'penumbra help' for usage)\n", error.what());
    return 2;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "penumbra: error: %s\n", error.what());
    return 1;
  }
}
