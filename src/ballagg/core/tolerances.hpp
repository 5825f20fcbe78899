#pragma once
// Every numerical tolerance of the event-driven model, with its unit and meaning.
// Lengths are relative to the contact distance sigma = R_i + R_j of the pair concerned
// (or to the smallest sphere diameter where no pair is involved); all are dimensionless.
// docs/model.md explains where each one is used and why its value is safe.

namespace ballagg::tolerance {

// Two spheres are "touching" when |X_i - X_j| <= sigma * (1 + kContact). Used for the
// contact cascade after a sticking collision (a sphere touching the new cluster at that
// instant sticks to it as well) and for the connectivity of glued clusters in input files.
inline constexpr double kContact = 1e-9;

// A pair is "approaching" only when (X_i - X_j).(V_i - V_j) < -kApproach |dX| |dV|.
// This keeps a pair that has just bounced with zero restitution (normal relative velocity
// zero up to round-off) from being predicted to collide again at the same instant.
inline constexpr double kApproach = 1e-12;

// A prediction that keeps only the earliest event of a cluster discards a contact when it
// certainly comes after the earliest found so far (collision/contact_time.hpp,
// contact_time_within): certainly, that is with this relative margin on the times and on
// the test's terms, far above round-off (about 2e-16 per operation), so that no contact at
// the very time of the kept event, or before it, is discarded.
inline constexpr double kHorizonMargin = 1e-12;

// A cluster whose extent along an axis is within kWallPinGap * (smallest diameter) of the
// box length touches both walls at once. It cannot move along that axis without bouncing
// infinitely often, so that velocity component is set to zero ("pinned", docs/model.md).
inline constexpr double kWallPinGap = 1e-9;

// Spheres read from an input file may overlap by at most this fraction of sigma, glued
// into one cluster or not (the time-stepping engine allows glued spheres its ts.eps_c):
// files written by ballagg itself contain contacts at sigma * (1 +- 1e-15).
inline constexpr double kInputOverlap = 1e-9;

// Spheres glued into one cluster in an input file must have the same velocity up to this
// fraction of the largest speed in the file.
inline constexpr double kGluedVelocity = 1e-9;

}  // namespace ballagg::tolerance
