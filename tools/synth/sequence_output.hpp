// sequence_output.hpp - ppcr_synth --sequence: a sequence's scans and its exact trajectory on
// disk (scans/scan_000000.ply ..., ground_truth_kitti.txt, ground_truth_tum.txt).
#pragma once

#include <string>

#include "ppcr/status.hpp"
#include "ppcr/synthetic.hpp"

namespace ppcr_synth {

/// Writes into out_dir (created if missing): scans/scan_NNNNNN.ply (six digits, more when
/// needed, in the sensor's frame), and the pose T_first_i of every scan i in the first scan's
/// frame to ground_truth_kitti.txt (3x4 per line) and ground_truth_tum.txt (t = i / rate_hz),
/// each line written as its scan is. kInvalidArgument for a bad option, kIoError for a file.
ppcr::Status write_sequence(const std::string& out_dir,
                            const ppcr::synthetic::SequenceOptions& options);

}  // namespace ppcr_synth
