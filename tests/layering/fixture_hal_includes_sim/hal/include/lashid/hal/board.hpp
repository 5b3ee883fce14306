// Fixture of the layering check: the HAL including the simulator, the back edge the check must refuse.
#pragma once
#include "lashid/hal/status.hpp"
#include "lashid/sim/scenario.hpp"
