#pragma once
// The 3-D displacement of one quasi-rigid area (docs/vectors.md; the thesis on rigid patches
// in TLS point clouds, §5.3): the area of the reference registered on its own to the epoch by
// least-squares matching of its surface and its intensities (Gruen & Akca 2005, "Least
// squares 3D surface and curve matching"; Akca 2007, "Matching of 3D surfaces and their
// intensities"), in the area's frame: u, v in its plane, w along its normal.
//
// Model. Both epochs' samples are resampled on one grid of the area's plane (pixels of one
// point spacing) by local linear regression (an image that slides smoothly with the texture,
// whatever the two scans' sample lattices): intensities I and heights W. The epoch is the
// reference moved by t along the surface and by t_w along the normal (least-squares image
// matching, Gruen 1985, with the heights as a second channel as in least squares 3D surface
// matching):
//     W_e(p + t_uv) = W_r(p) + t_w + e_w,      I_e(p + t_uv) = g·I_r(p) + c + cᵀ_uv·p + e_I
// over the reference's pixels p, the epoch evaluated at p + t_uv itself (no interpolation
// between pixels, whose error would lock the shift onto whole pixels), the Jacobian from the
// reference's intensity gradient, with the epoch's radiometry — gain g, offset c and its
// slope c_uv across the area — as nuisance parameters: a ramp of brightness (weathering,
// moisture, the angle of incidence) is no texture, since a ramp moved along itself is the same
// ramp with another offset. The heights fix t_w; along the surface only the intensity gradients
// (texture: formwork joints, tie holes, aggregate) fix t_u, t_v. The heights' own gradients
// are left out: a face has none, and at an edge the local planes' slope along the edge is
// the step's misfit rather than noise — it moved a textureless area with a step tens of
// millimetres along its edge. Each intensity gradient component is kept only where it is
// significant against the samples' noise (a gradient of noise is no texture), so a smooth,
// uniform area leaves t_u, t_v unobserved, and its covariance says so; such an area (σ along
// the surface beyond `max_sigma`) gives no vector.
//
// Solution. Coarse: the whole-pixel shift of largest normalised cross-correlation of the
// intensity images within `search_radius`. Fine: Gauss–Newton on both groups, each weighted
// by its robust residual variance (1.4826 × MAD, a variance-component estimate that a stray
// return cannot inflate), residuals beyond `clip` of it about the group's median left out;
// on every second pixel until it converges, then one step on every pixel.
//
// Covariance. Neighbouring pixels share samples, footprints and texture, so their residuals
// are not independent and N⁻¹ is optimistic. The covariance is the jackknife over square
// blocks of `block` metres (the cluster-robust estimator of Liang & Zeger 1986 in its
// jackknife form, CR3; Cameron & Miller 2015): each block's one-step influence
// d_b = (B − B_b)⁻¹·g_b, g_b = Σ_{p∈b} J_p w_p f_p, Σ = (G − 1)/G·Σ_b Σ_b' k_bb' d_b d_b'ᵀ,
// which holds whatever the correlation inside a block; neighbouring blocks, which share the
// samples along their border, enter with Bartlett weights k (1/2 beside, 1/4 across a corner:
// Conley 1999), and with few blocks Σ is scaled to Student's t(G − 1). B = Σ J_p w_p ∂f_p/∂xᵀ
// takes f's own derivative from the epoch, so a gradient that only noise observes averages
// out of it. A weak prior about the start (kPriorSigma) is added to B, and its variance to
// Σ, so a direction the data do not observe has the prior's σ, not a singular matrix.
#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <span>

namespace tlsmon::vectors {

// A sample in the area's frame: (u, v, w) m and its intensity (any linear scale).
struct AreaSample {
    float u = 0, v = 0, w = 0, intensity = 0;
};

// The images' kernel radius, in point spacings (quartic kernel; σ ≈ one spacing).
inline constexpr double kKernelRadiusSpacings = 2.5;
// m: the prior σ of the displacement about its start. A direction no sample observes keeps
// it: an area of a smooth, uniform face has no displacement along the surface, and says so.
inline constexpr double kPriorSigma = 0.05;

struct Parameters {
    double search_radius = 0.02;  // m, the coarse step's largest shift along the surface
    double block = 0.25;          // m, the side of the covariance's blocks
    int min_points = 200;         // reference and epoch samples an area needs
    int min_blocks = 8;           // blocks with samples (the covariance's clusters)
    double clip = 3.5;            // robust σ beyond which a residual is left out
    int max_iterations = 30;
    // m: an area whose σ along the surface (in its worst direction) exceeds this has no vector:
    // its texture does not observe the movement there.
    double max_sigma = 0.001;
    // m: an area the scan samples coarser than this (its samples' mean spacing on the surface)
    // gives no vector: its intensity image is aliased, the match follows the scan's lattice as
    // the scanner drifts, not the surface, and the covariance does not see it (every block
    // shares the lattice). It stands for the scanner's footprint at the structure, as
    // keypoints.max_sample_spacing (docs/vectors.md, "Sampling").
    double max_spacing = 0.02;
};

// The largest ratio of the coarsest to the finest sample spacing among an area's blocks (in
// either epoch) for a vector: beyond it the area straddles a change of the scan's sampling.
inline constexpr double kMaxSamplingRatio = 1.5;

enum class AreaOutcome {
    measured,
    few_points,
    few_blocks,
    singular,
    untextured,
    diverged,
    mixed_sampling,  // across a change of the scan's sampling (kMaxSamplingRatio)
    undersampled     // sampled coarser than max_spacing
};
const char* outcome_name(AreaOutcome outcome);

struct AreaVector {
    AreaOutcome outcome = AreaOutcome::few_points;
    Eigen::Vector3d displacement =  // (t_u, t_v, t_w), m
        Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();        // m², cluster-robust
    Eigen::Matrix3d model_covariance = Eigen::Matrix3d::Zero();  // m², N⁻¹ (independent)
    double gain = 1, offset = 0;
    double sigma_height = 0, sigma_intensity = 0;  // robust σ of the two groups' residuals
    double coarse_correlation = 0;                 // NCC at the coarse step's shift
    double spacing = 0;                            // m, the reference's point spacing
    std::size_t reference_points = 0, epoch_points = 0;
    std::size_t used = 0;    // residuals kept (heights and intensities)
    std::size_t blocks = 0;  // blocks with a kept residual
    int iterations = 0;
    bool measured() const { return outcome == AreaOutcome::measured; }
};

// The area's displacement from `reference` to `epoch` (both in the area's frame; the epoch
// already mapped into the reference frame by the global registration).
AreaVector register_area(std::span<const AreaSample> reference, std::span<const AreaSample> epoch,
                         const Parameters& parameters = {});

// Throws Error naming the parameter when a value cannot give a meaningful result.
void validate(const Parameters& parameters);

}  // namespace tlsmon::vectors
