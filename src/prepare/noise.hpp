#pragma once
// How noisy a scan is: a robust scale of the residuals to local quadric fits
// (estimate_noise), and whether it calls for smoothing.
#include <vector>

#include "prepare/prepare.hpp"

namespace vmas {


// The smallest neighbourhood estimate_noise fits (NoiseEstimate::neighbours).
inline constexpr int kFewestNoiseNeighbours = 16;

// Fits a quadric height field to the k nearest neighbours of evenly spread points (within an even
// subset of 10 000 points) and takes the median RMS residual, at the smallest k in 16, 32, ...
// 2048 whose neighbourhood radius is at least three times that residual (smaller neighbourhoods
// lie inside the noise and underestimate it). Clean samples of a smooth surface give a tiny
// fraction of the spacing; sharp edges touch too few points to move the median. Deterministic.
// Throws InvalidInput for fewer than kFewestNoiseNeighbours points.
NoiseEstimate estimate_noise(const std::vector<Vec3>& points);

// True when `noise` calls for smoothing under `options`.
bool is_noisy(const NoiseEstimate& noise, const DenoiseOptions& options);

// The robust deviation (median distance / 0.6745) by which smooth_mls(points, radius) would move
// the points, measured at about `samples` of them spread evenly through the array: the surface
// is fitted only where they are, and each distance is the one smooth_mls gives that point.
// Throws std::logic_error when samples < 1 or radius <= 0.
double mls_deviation(const std::vector<Vec3>& points, double radius, int samples);

}  // namespace vmas
