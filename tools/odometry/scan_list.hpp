// scan_list.hpp - the scans of a sequence, from the command line's inputs: files as given, in
// their order, and folders expanded to their cloud files in natural order.
#pragma once

#include <string>
#include <vector>

#include "ppcr/status.hpp"

namespace ppcr_odometry {

/// Each input that is a folder is replaced by its regular files whose extension names a cloud
/// format (.ply .pcd .xyz .txt .csv .pts .bin, any case; hidden files skipped), sorted by
/// natural_less on the file name; any other input is kept as given (it is read, and its errors
/// reported, when its turn comes). Fails when a folder cannot be listed or holds no cloud file.
ppcr::Status list_scans(const std::vector<std::string>& inputs, std::vector<std::string>* scans);

}  // namespace ppcr_odometry
