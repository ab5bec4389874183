#include <cstdio>
#include <fstream>
#include <sstream>

#include "interchange/scene_import.h"
#include "cli/commands.h"

namespace penumbra::cli {

namespace {

// "r,g,b" (or one number for grey).
Vec3 parseRadiance(const std::string& text) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) {
    try {
      size_t used = 0;
      values.push_back(std::stod(part, &used));
      if (used != part.size()) values.clear();
    } catch (const std::exception&) {
      values.clear();
    }
    if (values.empty()) break;
  }
  if (values.size() == 1) return Vec3(values[0]);
  if (values.size() == 3) return Vec3(values[0], values[1], values[2]);
  throw UsageError("--light-radiance must be r,g,b (or one number), got '" + text + "'");
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

}  // namespace

int runImport(const Args& args) {
  args.allowOnly({"out", "light-radiance", "scale", "report"});
  const std::string input = args.positional(0, "FILE");
  const auto out = args.option("out");
  if (!out) throw UsageError("import needs --out SCENE");
  interchange::ImportOptions options;
  options.scale = args.doubleOption("scale", 1);
  options.studio = !args.flag("no-studio");
  if (const auto radiance = args.option("light-radiance")) options.lightRadiance = parseRadiance(*radiance);

  const interchange::ImportResult result = interchange::importSceneFile(input, options);
  writeText(*out, result.sceneJson.dump(2) + "\n");
  if (const auto report = args.option("report")) writeText(*report, result.report.toJson().dump(2) + "\n");
  std::fputs(result.report.summary().c_str(), stderr);
  std::printf("wrote %s: %zu objects, %zu faces, %zu lights\n", out->c_str(), result.report.objects,
              result.report.faces, result.report.lights);
  return 0;
}

}  // namespace penumbra::cli
