#pragma once
/// Spring stiffness of a sheet from its material's Young's modulus and its thickness: k = E times a length per spring.
///
/// A triangular (TRiMM) layer of equilateral triangles with springs k is an isotropic membrane of Young's modulus
/// E t = (2/sqrt 3) k and Poisson's ratio 1/3, so k = (sqrt(3)/2) E t (physics.md section 3). The triangles are
/// equilateral when the row spacing is sqrt(3)/2 of the column spacing, depth / (NZ - 1) = (sqrt(3)/2) width /
/// (NX - 1/2); other aspect ratios make the membrane anisotropic (Table 1's square sheet box at 8x2x8 puts the rows
/// 1.07 column spacings apart instead of 0.87, which makes it softer across the rows than along them). A square layer
/// with springs k along its grid lines stretches along an axis with E t = k (and no Poisson contraction); MaSSE gives
/// every planar spring of square lattices k = E t, braces (SLaMM) included, which makes SLaMM somewhat stiffer than E
/// along the axes and SaMM soft in shear: the square lattices are the paper's, not a calibrated membrane.
///
/// The L layers share the thickness: the planar springs of each layer stand for t/L, so the in-plane stiffness
/// stays about E t whatever the number of layers. Inter-layer springs set bending and hold the layers together;
/// they take the paper's Table 1 ratio to a planar spring, 6.2/9.2 (inter-layer 6.2 g/mm, planar 9.2 g/mm). Being
/// slanted, they also add some in-plane stiffness (at most about a tenth for a thin two-layer TRiMM sheet).

#include "core/lattice/Lattice.h"

#include <vector>

namespace masse
{
/// The paper's Table 1 ratio of inter-layer to planar stiffness.
inline constexpr Real paperInterLayerRatio = 6.2 / 9.2;

/// k / E for every spring of the lattice (m), in the lattice's spring order, for a sheet of the given thickness (m).
/// Throws InputError for a non-positive thickness or ratio.
std::vector<Real> stiffnessPerModulus(const Lattice& lattice, Real thickness,
                                      Real interLayerRatio = paperInterLayerRatio);
} // namespace masse
