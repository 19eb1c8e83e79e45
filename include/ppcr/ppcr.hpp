// ppcr.hpp - umbrella include of the ppcr core (ppcr_io has its own header, ppcr/io.hpp).
#pragma once

#include "ppcr/metrics.hpp"
#include "ppcr/options.hpp"
#include "ppcr/registration.hpp"
#include "ppcr/result.hpp"
#include "ppcr/se3.hpp"
#include "ppcr/status.hpp"
#include "ppcr/types.hpp"
#include "ppcr/version.hpp"
#include "ppcr/voxel.hpp"
