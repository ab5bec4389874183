#include <cstdio>

#include "bench/lib/cubes_scene.h"
#include "bench/lib/dense_scene.h"
#include "bench/lib/sphere_scene.h"
#include "protocol/scene_json.h"
#include "cli/commands.h"

namespace penumbra::cli {

namespace {

// `--dense`: N boxes of random size and orientation floating in a 6 × 3 × 6 m room.
Scene denseScene(const Args& args) {
  if (args.flag("tilted-light") || args.flag("two-lights") || args.option("light-scale") ||
      args.option("stacked-fraction") || args.option("tables"))
    throw UsageError("--dense takes only --cubes, --seed and --out");
  DenseSceneOptions options;
  options.boxes = args.intOption("cubes", options.boxes, 0, 100000);
  options.seed = uint64_t(args.intOption("seed", int(options.seed), 0, 1 << 30));
  return makeDenseScene(options);
}

// `--sphere FACES`: one UV sphere of about FACES faces (radius 0.35 m) in the dense room.
Scene sphereScene(const Args& args) {
  if (args.flag("dense") || args.flag("tilted-light") || args.flag("two-lights") || args.option("cubes") ||
      args.option("seed") || args.option("light-scale") || args.option("stacked-fraction") || args.option("tables"))
    throw UsageError("--sphere takes only FACES and --out");
  SphereSceneOptions options;
  options.faces = args.intOption("sphere", options.faces, 6, 1000000);
  return makeSphereScene(options);
}

}  // namespace

int runGenerate(const Args& args) {
  if (args.option("volume")) return runGenerateVolume(args);
  args.allowOnly({"cubes", "seed", "light-scale", "stacked-fraction", "tables", "out", "sphere"});
  CubesSceneOptions options;
  options.cubes = args.intOption("cubes", options.cubes, 0, 100000);
  options.seed = uint64_t(args.intOption("seed", int(options.seed), 0, 1 << 30));
  options.lightScale = args.doubleOption("light-scale", options.lightScale);
  options.stackedFraction = args.doubleOption("stacked-fraction", options.stackedFraction);
  options.thinTables = args.doubleOption("tables", options.thinTables);
  options.tiltedLight = args.flag("tilted-light");
  options.twoLights = args.flag("two-lights");
  if (!(options.lightScale > 0 && options.lightScale <= 1))
    throw UsageError("--light-scale must be in (0, 1]");
  if (!(options.stackedFraction >= 0 && options.stackedFraction <= 1))
    throw UsageError("--stacked-fraction must be in [0, 1]");
  if (!(options.thinTables >= 0 && options.thinTables <= 1))
    throw UsageError("--tables must be a fraction in [0, 1]");
  const auto out = args.option("out");
  if (!out) throw UsageError("generate needs --out SCENE");

  const Scene scene = args.option("sphere") ? sphereScene(args)
                      : args.flag("dense")   ? denseScene(args)
                                             : makeCubesScene(options);
  protocol::saveSceneFile(scene, *out);
  std::printf("wrote %s: %zu objects, %zu faces, %zu lights\n", out->c_str(),
              scene.objects().size(), scene.faces().size(), scene.lights().size());
  return 0;
}

}  // namespace penumbra::cli
