#pragma once
/// A sheet's masses and springs from its material, thickness and temperature.
///
/// Each mass carries its layer's share of the material over the area it stands for at rest (SheetThickness),
/// m_i = rho (h0/L) A0_i, so the sheet weighs rho h0 A like the real one and edge masses are lighter than inner ones,
/// as their areas are; this is the same lumping ThermalModel uses for heat capacity. Each spring gets
/// k = g E(T) (MembraneStiffness.h) and a dashpot of `dampingRatio` of critical. ViscoelasticSprings then takes the
/// coefficients over; the masses stay.

#include "core/MassSpringSystem.h"
#include "core/lattice/Lattice.h"
#include "core/material/Material.h"
#include "core/material/MembraneStiffness.h"

namespace masse
{
/// Throws InputError for a bad material, thickness, temperature or damping ratio (outside [0, 1]).
MassSpringSystem makeMaterialSheet(const Lattice& lattice, const Material& material, Real thickness, Real temperature,
                                   Real dampingRatio = 0.06, Real interLayerRatio = paperInterLayerRatio);
} // namespace masse
