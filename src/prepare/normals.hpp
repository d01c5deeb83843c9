#pragma once
// Normal estimation for point clouds that come without normals, and consistent outward
// orientation (minimum spanning tree propagation over the k-NN graph, Hoppe et al. 1992, then a
// global check that the normals point away from the inside).
#include <vector>

#include "core/cloud_graph.hpp"
#include "prepare/prepare.hpp"

namespace vmas {

// Unit normals, one per point, from a plane fit to each point and its k nearest neighbours, then
// oriented as by orient_normals. Throws InvalidOption for a bad k and InvalidInput for fewer than
// k + 1 points. Deterministic whatever the thread count; never returns NaN (a degenerate
// neighbourhood gets a finite normal whose line may be arbitrary).
std::vector<Vec3> estimate_normals(const std::vector<Vec3>& points, const NormalOptions& options);
// As above, with the points' neighbourhoods already found: k_nearest_all(points, options.k).
std::vector<Vec3> estimate_normals(const std::vector<Vec3>& points, const NormalOptions& options,
                                   const internal::Neighbourhoods& neighbours);

// The file's normals replaced by the normals of the surface that the points sample, each with its
// file normal's sign: `fitted` (one per point, unoriented; NaN where unknown) or, when empty, plane
// fits to k neighbours as in estimate_normals. A file's normals can be exact for the facets the
// points were sampled from, or for each point alone, and tilt from point to point; the
// skeleton's quadrics and shrinking balls want the surface's at the sampling's scale (the
// benchmark's clean clouds with their facets' normals: ε 1.24 → 1.06 % on average). A file normal
// stays where the fit is unknown or more than 60 degrees off it (a fit straddling two sheets or an
// edge), and where the cloud is too small for fits. NaN or zero file normals are filled first
// (fill_missing_normals, which throws for fewer than k + 1 points); a file normal that stays
// keeps its length. Throws InvalidInput when the sizes differ.
void refit_given_normals(const std::vector<Vec3>& points, std::vector<Vec3>& normals, int k,
                         std::vector<Vec3> fitted = {});

// Flips given normals so that neighbours agree and each connected component of the k-NN graph
// points outward. Also normalises them and replaces NaN or zero ones by finite ones. Throws
// InvalidOption for a bad k and InvalidInput when the two sizes differ.
void orient_normals(const std::vector<Vec3>& points, std::vector<Vec3>& normals, int k);

// Orients the normals of a smoothed noisy cloud as orient_normals does, then turns over each
// region (at least 2 % of the points, joined along clearly agreeing neighbours) whose normals
// views from outside see facing away (visibility_votes, smoothed over the k-NN graph with the
// signs that neighbouring normals' agreement gives). Strong noise's smoothing folds facing parts
// together, and propagation along a spanning tree flips whole regions at one wrong step there
// (the benchmark's clouds at σ = 3 %: 30-63 % of the normals inward on 9 of 12 models); the
// views' own mistakes are scattered (thin parts seen from both sides, cavities) and too small
// to turn anything. Throws as orient_normals.
void orient_smoothed_normals(const std::vector<Vec3>& points, std::vector<Vec3>& normals, int k);

// The share of neighbouring normals on one sheet (each point and its 8 nearest neighbours that lie
// near its tangent plane: not across a thin part) that point opposite ways: near 0 for oriented
// normals, whatever the shape (a fold sharper than a right angle is rare), near ½ for normals
// of arbitrary sign (estimated elsewhere, oriented by no rule). 0 for fewer than 9 points.
double sign_disagreement(const std::vector<Vec3>& points, const std::vector<Vec3>& normals);

// How much unit normals point away from the points' centroid: Σ (p − c)·n / Σ |p − c| over the
// points listed in `subset` (all when empty), in [−1, 1]. Near 1 for a roundish closed surface
// with outward normals, near −1 with inward ones, near 0 for flat data or normals of random sign.
double outward_flux(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                    const std::vector<int>& subset = {});

}  // namespace vmas
