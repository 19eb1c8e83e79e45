// ppcr.hpp - umbrella include of the ppcr core (ppcr_io has its own header, ppcr/io.hpp).
#pragma once

#include "ppcr/error_model.hpp"
#include "ppcr/lm.hpp"
#include "ppcr/metrics.hpp"
#include "ppcr/registration.hpp"
#include "ppcr/se3.hpp"
#include "ppcr/status.hpp"
#include "ppcr/termination.hpp"
#include "ppcr/types.hpp"
#include "ppcr/version.hpp"
#include "ppcr/voxel.hpp"
#include "ppcr/weights.hpp"
