// The `penumbra` subcommands. Each returns the process exit status
// (0 ok, 1 failure, 2 bad input or usage) and prints results to stdout,
// progress and errors to stderr.
#pragma once

#include "core/engine/engine.h"

#include "cli/cli_args.h"

namespace penumbra::cli {

int runValidate(const Args& args);
int runInfo(const Args& args);
int runReference(const Args& args);
int runGenerate(const Args& args);
int runGenerateVolume(const Args& args);  // generate --volume
int runBuild(const Args& args);
int runImport(const Args& args);
int runRender(const Args& args);
int runServe(const Args& args);
int runReplay(const Args& args);

// --mesh-tolerance F (build, render, replay, serve): EngineSettings::meshTolerance, in [0, 0.5]
// (0: no refinement); `fallback` when absent.
double meshToleranceOption(const Args& args, double fallback = EngineSettings::kRecommendedMeshTolerance);
// serve's default: no refinement. Refining the cells an edit touches costs 15–30× their fans
// (cubes15: 20–45 ms a drag frame instead of 1.4 ms), which halves the edits/s one server
// sustains; live editing keeps the fans unless --mesh-tolerance asks (docs/SERVER.md).
inline constexpr double kServeMeshTolerance = 0;

}  // namespace penumbra::cli
