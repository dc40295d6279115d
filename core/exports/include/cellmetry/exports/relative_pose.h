// Moved to basics (cellmetry/basics/relative_pose.h) so that the cell pipeline writes the same
// robot-to-robot transforms the tf export comments; this header stays for existing includes.
#pragma once

#include "cellmetry/basics/relative_pose.h"
