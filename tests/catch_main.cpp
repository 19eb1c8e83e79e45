// The Catch2 main of the unit tests that need no data.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
