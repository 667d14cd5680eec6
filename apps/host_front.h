// The hosts' front ends (one file each), internal to the command line: scene to solution.
#pragma once
#include "host_table.h"

/// BRIGHT-like (base_radiosity): tessellate, quadtree hierarchy, stored links, gathering.
HostResult solveBright(HostJob& job);
/// VISION-like (vision_host): whole primitives, bounded radiosity, link-less shooting.
HostResult solveVision(HostJob& job);
/// Resets job.ext when no material of the scene is one the extension simulates.
void dropUnneededExtension(HostJob& job);
