// registration_flags.hpp - the registration options of ppcr_cli and ppcr_bench (a contract:
// scripts depend on these names), bound to a CLI11 app and turned into RegistrationOptions.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "ppcr/registration.hpp"
#include "ppcr/status.hpp"

namespace ppcr_tools {

/// Raw flag values as typed by the user (validated by to_options()).
struct RegistrationFlags {
  double radius = ppcr::RegistrationOptions().radius;
  int max_neighbours = ppcr::RegistrationOptions().max_neighbours;
  double dof = ppcr::WeightOptions().dof;
  bool gaussian = false;
  std::string scale = "em";                               // em | raw | <s>
  double coarse_scale = 0.0;                              // EM's coarse scale (0 = radius / 2)
  double min_scale = ppcr::WeightOptions().em_min_scale;  // EM's floor on s (0 = none)
  std::string criterion = "cost-drop";                    // comma-separated list
  double cost_drop_threshold = ppcr::TerminationCriteria().cost_drop_threshold;
  int patience = ppcr::TerminationCriteria().cost_drop_patience;
  int max_iterations = ppcr::TerminationCriteria().max_iterations;
  double mse_ratio = ppcr::TerminationCriteria().mse_ratio_threshold;
  int mse_patience = ppcr::TerminationCriteria().mse_patience;
  int steps_threshold = ppcr::TerminationCriteria().successful_steps_threshold;
  std::string error_model =
      ppcr::RegistrationOptions().error_model == ppcr::ErrorModel::kPlane ? "plane" : "point";
  double plane_epsilon = ppcr::PlaneOptions().epsilon;
  int normal_neighbours = ppcr::PlaneOptions().normal_neighbours;
  bool source_normals = ppcr::PlaneOptions().source_normals;
  double noise_floor = ppcr::PlaneOptions().noise_floor;
  double motion_guard =
      ppcr::TerminationCriteria()
          .cost_drop_max_motion;  // cost-drop / coarse-phase motion guard (fraction of radius)
  int coarse_patience = ppcr::WeightOptions().em_coarse_patience;
  double scale_shrink = ppcr::WeightOptions().em_min_shrink;  // EM: s^2 shrink limit per iteration
  double reassociate_motion = ppcr::RegistrationOptions().reassociate_motion;
  int neighbour_cache = ppcr::RegistrationOptions().neighbour_cache;
  std::string coarse_stride = "auto";  // EM coarse phase: auto (RegistrationOptions::kAutomatic)
                                       // or an integer in [1, 64]
  double lm_tolerance = ppcr::LMOptions().function_tolerance;  // inner LM
  std::string lm_fine_tolerance = "auto";  // EM fine phase: auto (LMOptions::kAutomatic) or >= 0
  double source_voxel = 0.0;
  double target_voxel = 0.0;
  int threads = 1;
};

/// Adds --radius, --max-neighbours, --dof, --gaussian, --scale, --coarse-scale, --min-scale,
/// --criterion, --cost-drop-threshold, --patience, --max-iterations, --mse-ratio, --mse-patience,
/// --steps-threshold, --error-model, --plane-epsilon, --normal-neighbours, --source-normals,
/// --noise-floor, --motion-guard, --coarse-patience, --scale-shrink, --neighbour-cache,
/// --lm-tolerance, --lm-fine-tolerance, --source-voxel, --target-voxel, --threads.
void add_registration_flags(CLI::App& app, RegistrationFlags* flags);

/// Validates the flags and fills options. The message names the flag and the value seen.
ppcr::Status to_options(const RegistrationFlags& flags, ppcr::RegistrationOptions* options);

}  // namespace ppcr_tools
