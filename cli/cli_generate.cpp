#include <cstdio>

#include "cli/commands.h"
#include "protocol/scene_json.h"
#include "scenegen/cubes_scene.h"
#include "scenegen/dense_scene.h"
#include "scenegen/model_scene.h"
#include "scenegen/sphere_scene.h"

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

// `--model NAME`: one procedural model (or the furnished room) in the dense room. Prints
// what it wrote: the models' triangles and whether each is closed.
int runGenerateModel(const Args& args) {
  args.allowOnly({"model", "triangles", "seed", "out"});
  if (args.flag("dense") || args.flag("tilted-light") || args.flag("two-lights"))
    throw UsageError("--model takes only --triangles, --rest, --smooth, --seed and --out");
  const auto kind = modelKindFromName(*args.option("model"));
  if (!kind)
    throw UsageError("--model must be one of " + modelKindNames() + ", got '" +
                     *args.option("model") + "'");
  ModelSceneOptions options;
  options.kind = *kind;
  options.triangles = args.intOption("triangles", defaultModelTriangles(*kind),
                                     minModelTriangles(*kind), kMaxModelTriangles);
  options.rest = args.flag("rest");
  options.smooth = args.flag("smooth");
  if (options.rest && *kind == ModelKind::Furnished)
    throw UsageError("--rest does not apply to --model furnished (each object has its place)");
  options.seed = uint64_t(args.intOption("seed", int(options.seed), 0, 1 << 30));
  const auto out = args.option("out");
  if (!out) throw UsageError("generate needs --out SCENE");

  const Scene scene = makeModelScene(options);
  protocol::saveSceneFile(scene, *out);
  size_t triangles = 0, closed = 0, models = 0;
  std::string open;
  for (const Object& object : scene.objects()) {
    if (object.isStatic || object.id.rfind("table_", 0) == 0) continue;  // the room, tables
    ++models;
    triangles += object.faces.size();
    if (meshEdges(objectMesh(object)).closed())
      ++closed;
    else
      open += (open.empty() ? "" : ", ") + object.id;
  }
  std::printf("wrote %s: %s, %zu model triangles (%zu faces in all, %zu objects), %s, %s%s\n",
              out->c_str(), modelKindName(*kind), triangles, scene.faces().size(),
              scene.objects().size(),
              options.rest                    ? "resting on the floor"
              : *kind == ModelKind::Furnished ? "placed"
                                              : "floating",
              models == 1 ? (closed ? "closed" : "open (not watertight)")
                          : (std::to_string(closed) + " of " + std::to_string(models) +
                             " models closed; open: " + open)
                                .c_str(),
              options.smooth ? ", smooth-shaded (corner normals)" : "");
  return 0;
}

}  // namespace

int runGenerate(const Args& args) {
  if (args.option("volume")) return runGenerateVolume(args);
  if (args.option("model")) return runGenerateModel(args);
  if (args.flag("rest") || args.flag("smooth") || args.option("triangles"))
    throw UsageError("--rest, --smooth and --triangles need --model NAME");
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
