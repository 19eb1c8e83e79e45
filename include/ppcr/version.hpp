// version.hpp - the library's version.
#pragma once

#define PPCR_VERSION_MAJOR 0
#define PPCR_VERSION_MINOR 1
#define PPCR_VERSION_PATCH 0
#define PPCR_VERSION_STRING "0.1.0"
