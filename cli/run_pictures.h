// What `probebake run` adds to the runtime-only driver, because it needs the scene and the path tracer: at
// chosen frames of an animated run (--at-frames), irradiance images of the runtime's probes in the
// scene's current pose (--images DIR: final = direct + indirect, and indirect only; EXR and PNG) and the
// error of the runtime's indirect irradiance against a path-traced reference of that pose (--reference:
// error.csv and error.svg in DIR). Issue #12 "Error against run time, in motion".
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "probebake/eval/reference.h"
#include "probebake/runtime/runtime.h"
#include "probebake/scene/scene.h"

namespace probebake::cli {

struct RunPictureOptions {
  std::string scene;          // the glTF the volume was baked from
  std::string folder;         // output folder
  std::vector<int> at_frames; // 0-based frames
  bool images = false;
  bool reference = false;
  std::optional<bake::Camera> camera; // checked; default: the scene's first camera, else one facing the bounds from +Z
  int receivers = 256;
  int paths = 256;
  // --day-cycle SECONDS: the reference of a frame is lit by that frame's physical sky and sun (the scene's sky must be
  // physical), as the runtime's day cycle lights it.
  std::optional<float> day_cycle;
};

class RunPictures {
public:
  RunPictures(RunPictureOptions options, scene::Scene scene);
  // After frame `frame` of the run: pictures and error when it is one of the chosen frames.
  runtime::Status after_frame(int frame, runtime::Volume& volume);
  // error.csv and error.svg when the reference was asked for; returns the files written.
  std::vector<std::string> finish() const;

private:
  struct ErrorRow {
    int frame = 0;
    float hour = -1.0f; // the day cycle's, else -1
    double relative_rmse = 0, relative_median = 0, reference_noise = 0, mean_reference = 0, mean_runtime = 0,
           seconds = 0;
  };
  scene::Scene posed_scene(const runtime::Volume& volume, float hour) const;
  void write_images(int frame, const scene::Scene& posed, runtime::Volume& volume);
  ErrorRow measure(int frame, float hour, const scene::Scene& posed, runtime::Volume& volume) const;

  RunPictureOptions options_;
  scene::Scene scene_;
  std::vector<ErrorRow> errors_;
  float exposure_ = 0.0f; // PNG scale, fixed by the first image so that all frames compare
};

} // namespace probebake::cli
