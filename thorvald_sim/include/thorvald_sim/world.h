#pragma once

// Every world the simulator builds: the description type and flat floor, the greenhouse, the cotton row.
#include "thorvald_sim/cotton_world.h"
#include "thorvald_sim/greenhouse_world.h"
#include "thorvald_sim/world_description.h"
