#pragma once

#include "greenhouse_rail_nav/depth_camera.h"

namespace greenhouse_rail_nav {

/// Edge-preserving smoothing of an active-stereo depth image before the rails are searched in it: every point
/// with depth is moved along its own ray to the median range of the points with depth in the window x window
/// pixels around it (window odd, >= 3; at least half the window's pixels must have depth, else the point stays).
/// Pixels without depth stay without. An active-stereo camera's range noise grows with the square of the range
/// (about 2 % at 2 m for the D400 class): at the far end of the rails' search region the noise in height is as
/// large as the pipes' height band, and floor points fill the band. A median over 5 x 5 pixels cuts independent
/// pixel noise about four-fold while keeping the step between a pipe and the floor behind it (the pipe stays the
/// majority of its pixels' windows down to about 9 px of pipe, 2.5 m away). window <= 1 returns the cloud as it is.
OrganisedCloud medianAlongRays(const OrganisedCloud& cloud, int window);

}  // namespace greenhouse_rail_nav
