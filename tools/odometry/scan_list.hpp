// scan_list.hpp - the scans of a sequence, from the command line's inputs: files as given, in
// their order, and folders expanded to their cloud files in natural order.
#pragma once

#include <string>
#include <vector>

#include "ppcr/status.hpp"

namespace ppcr_odometry {

/// Each input that is a folder is replaced by its scans: a TUM RGB-D folder (one with a depth/
/// subfolder) by the depth images of depth/ (their names are their timestamps, so natural order is
/// time order); any other folder by the regular files of its most common cloud
/// extension (.ply .pcd .xyz .txt .csv .pts .bin .png, any case; on a tie, the first in
/// alphabetical order; hidden files skipped), sorted by natural_less on the file name. A folder
/// holds the scans of one format: its other files (a ground truth .txt beside .xyz scans, a
/// times.txt beside .bin frames) are never read as scans; when `skipped` is given, one line per
/// folder that had any names them. Any other input is kept as given (it is read, and its errors
/// reported, when its turn comes). Fails when a folder cannot be listed or holds no cloud file.
ppcr::Status list_scans(const std::vector<std::string>& inputs, std::vector<std::string>* scans,
                        std::vector<std::string>* skipped = nullptr);

/// The scans' times when every file name is one (TUM's "1305031229.528784.png": digits, a point,
/// digits, then the extension); else false and *times empty.
bool times_from_names(const std::vector<std::string>& scans, std::vector<double>* times);

}  // namespace ppcr_odometry
