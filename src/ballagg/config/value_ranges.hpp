#pragma once
// The ranges of input values in which every engine's arithmetic stays finite and
// resolvable: positions, times, energies, momenta and the event calendar's keys.
// docs/hardening.md ("Finite but extreme values") derives them; docs/configuration.md
// lists them with the keys. Values outside are refused before anything is written: by the
// configuration reader (config.cpp), by the state-file checks (initial/state_ranges.hpp)
// and after the defaults are resolved (the box from the volume fraction, the skin).
//
// The model is scale-free (only ratios of lengths, of masses and of speeds matter): a
// user picks units in which radii, masses and speeds are near 1. The bounds leave twenty
// and more decades either side of that, and are chosen so that at their corners
//   - every product the engines form stays far from overflow (1.8e308) and underflow
//     (2.2e-308): squared distances (at most (2 kMaxBoxLength)^2 = 4e52), contact-time
//     discriminants (box length * speed)^2 (~1e94), kinetic energy N m v^2 (~1e80),
//     angular momentum N m L v (~1e85), inertia N m L^2 (~1e91) and the triple products
//     of a 3x3 inertia tensor (~1e272), the smallest m R^2 cubed (1e-210);
//   - positions at the box's scale resolve a contact to the contact tolerance and the
//     neighbour-list skin to thousands of units in the last place (the ratio bounds).

namespace ballagg::range {

// Relative spacing of doubles (2^-52): a coordinate x is known to kRelativePrecision |x|.
inline constexpr double kRelativePrecision = 0x1p-52;

// Radii (system.radius, the radius column of a state file). With the box bound below,
// every length stays within 1e-20 .. 1e26, so its square and cube stay normal numbers.
inline constexpr double kMinRadius = 1e-20;
inline constexpr double kMaxRadius = 1e20;

// Masses of spheres: at most 10^8 of them, so a total mass of at most 1e38, whose products
// with squared speeds and lengths are bounded above; masses are only ever summed or
// divided by each other otherwise.
inline constexpr double kMinMass = 1e-30;
inline constexpr double kMaxMass = 1e30;

// Speeds (initial.speed, |v| of a state file's row; a spin times the sphere's radius): the
// kinetic energy and the contact-time discriminants are squares of speeds times masses or
// lengths. No lower bound: a slow sphere only takes long to arrive (kNever if never).
inline constexpr double kMaxSpeed = 1e20;

// Box length over the smallest radius: a coordinate at the box's scale is resolved to
// kRelativePrecision L, which must stay ten times below the contact tolerance
// (tolerance::kContact = 1e-9 of the contact distance 2 R): 2.2e-16 L / (2 R) <= 1e-10.
inline constexpr double kMaxBoxToRadius = 1e6;
inline constexpr double kMaxBoxLength = kMaxBoxToRadius * kMaxRadius;

// Neighbour-list skin over the smallest radius: each cluster's lists expire after it moved
// skin / 2, so the skin must be resolved by positions at the box's scale (at the smallest
// skin and the largest box, 1e-12 L: 4500 units in the last place) and its square must
// not underflow (a skin of 1e-300 would rebuild the lists at one instant for ever).
inline constexpr double kMinSkinToRadius = 1e-6;
// Neighbour-list skin over the box length: a longer skin lists every pair already; the
// bound keeps skin^2 finite. The default skin never exceeds 1.3 box lengths.
inline constexpr double kMaxSkinToBox = 10.0;

// The time-stepping engine's first step over the box crossing time (ts.dt_factor): each
// step moves the fastest sphere dt_factor L, which positions at the box's scale must
// resolve (1e-9 L: 4.5 million units in the last place); a smaller factor steps the time
// forward by amounts no position can follow.
inline constexpr double kMinDtFactor = 1e-9;

// Coordinates of a state file in a periodic box: at most this many box lengths outside
// [0, L]. Folding a coordinate far outside keeps its rounding error, which is relative to
// the coordinate, not to the box.
inline constexpr double kMaxPeriodicOverhang = 1.0;

}  // namespace ballagg::range
