// Error in motion (issue #12): the path-traced indirect irradiance of a scene in one pose of its dynamic
// objects, at receivers drawn in that pose, and the error of a runtime's irradiance there. `probebake run
// --animate ... --reference SCENE` calls it at chosen frames; `probebake reference --animate` traces a pose.
#pragma once

#include <vector>

#include "probebake/eval/eval.h"
#include "probebake/eval/reference.h"

namespace probebake::bake {

struct PoseReferenceSettings {
  ReceiverSettings receivers;  // default below: 256 visible receivers
  ReferenceSettings reference; // default below: 256 paths per receiver
  PoseReferenceSettings() {
    receivers.count = 256;
    reference.paths = 256;
  }
};

struct PoseReference {
  std::vector<SamplePoint> points;
  std::vector<glm::vec3> indirect;                // reference minus its direct part, W/m^2
  std::vector<glm::vec3> indirect_standard_error; // per point and channel
  double mean_indirect = 0.0;                     // over points and channels
  double seconds = 0.0;                           // receivers + path tracing
};

// `posed_scene` is the scene with every dynamic object where the runtime has it (scene::posed).
PoseReference pose_reference(const scene::Scene& posed_scene, const PoseReferenceSettings& settings);

struct PoseError {
  double relative_rmse = 0.0;   // RMS over points of |estimate - reference| (RGB RMS) / mean reference
  double relative_median = 0.0; // median of |error| / max(|reference|, 1% of the mean)
  double reference_noise = 0.0; // RMS standard error / mean reference: the floor of relative_rmse
  int points = 0;
};

// `indirect_estimate`: the runtime's probe irradiance at reference.points (their normals).
PoseError pose_error(const PoseReference& reference, const std::vector<glm::vec3>& indirect_estimate);

} // namespace probebake::bake
