#pragma once
// A run's configuration: read from TOML (a file, command-line --set overrides, or the
// embedded defaults), checked key by key, with errors that name the file line or the
// --set argument and what is allowed.
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ballagg/core/box.hpp"
#include "ballagg/core/input_error.hpp"
#include "ballagg/core/radius_distribution.hpp"
#include "ballagg/collision/collision_settings.hpp"
#include "ballagg/engines/rigid_body/rigid_body_settings.hpp"
#include "ballagg/engines/time_stepping/ts_settings.hpp"

namespace ballagg {

enum class InitialPositions { lattice, random, file };
enum class InitialVelocities { fixed_speed, uniform, gaussian };
enum class EngineKind { ed, ed_naive, ts, rigid_body };

struct SystemConfig {
  int dimension = 2;
  std::int64_t n = 2500;
  std::optional<double> volume_fraction;  // 0.2 when neither this nor box_length is given
  std::optional<double> box_length;
  double radius = 0.2;  // the radius R_0: of every sphere, or the reference of radius_distribution
  double mass = 1.0;    // of a sphere of radius R_0; others m_0 (R / R_0)^D
  Boundary boundary = Boundary::walls;
  RadiusDistribution radius_distribution;  // system.radius_distribution and its parameters
  std::optional<double> density;           // instead of mass: m = density * sphere volume
};

struct InitialConfig {
  InitialPositions positions = InitialPositions::lattice;
  InitialVelocities velocities = InitialVelocities::fixed_speed;
  double speed = 1.0;
  // The lattice's spacing, setting the box (L = sites per side x spacing) instead of
  // system.volume_fraction or system.box_length: Degond et al. 2023, App. A's unit lattice.
  std::optional<double> lattice_spacing;
  std::string file;                  // a state file, or a finished run's directory (resolved to its final.csv)
  double time = 0.0;                 // the simulated time the initial state is at
  bool zero_momentum = false;
  std::uint64_t seed = 1;
};

struct EngineConfig {
  EngineKind kind = EngineKind::ed;
  std::optional<double> skin;  // neighbour-list skin of ed and rigid-body; unset: the engine's default
};

struct StopConfig {
  std::int64_t clusters = 1;
  double time = std::numeric_limits<double>::infinity();
  double wall_seconds = std::numeric_limits<double>::infinity();
  std::optional<double> aggregated_fraction;  // rigid-body engine only
};

enum class SnapshotFormat { h5md, xyz, gsd };
// How trajectory.h5md stores positions and velocities: float32 (half the bytes) or float64.
enum class SnapshotPrecision { single, double_ };

struct OutputConfig {
  double timeseries_interval = 0.0;  // simulated time between extra rows; 0: none
  bool xyz = true;
  double snapshot_every = 0.0;       // simulated time between trajectory frames; 0: none
  std::vector<SnapshotFormat> snapshot_formats{SnapshotFormat::h5md};  // no duplicates
  SnapshotPrecision snapshot_precision = SnapshotPrecision::single;  // trajectory.h5md positions, velocities
  bool h5md_pad_3d = false;          // 2D runs: trajectory.h5md in 3D (z = 0), the layout 3D readers need
  double checkpoint_every = 300.0;   // wall seconds between checkpoints; 0: none (signals still write one)
};

// The engines' settings are members as the engines declare them: make_engine
// (run/simulation.hpp) hands them over whole.
struct Config {
  SystemConfig system;
  InitialConfig initial;
  CollisionSettings collision;  // [collision] outcome, restitution, tc_time: every engine's law
  RigidBodyLaw rigid_body;      // the [collision] keys of the rigid-body engine
  EngineConfig engine;
  StopConfig stop;
  OutputConfig output;
  TimeSteppingSettings ts;  // [ts], read always, used when engine.kind = "ts"
  std::string source = "(defaults)";  // where it was read from, for messages
  std::vector<std::string> set_arguments;  // the --set arguments applied, in order, for messages
};

// Where the values of `keys` ("section.key") came from, for a message about a rule that
// involves them: the --set arguments that gave any of them ("--set system.n=400 --set
// system.volume_fraction=0.6", the last one of each key), or else c.source.
std::string origin_of(const Config& c, std::initializer_list<std::string_view> keys);

inline constexpr double kDefaultVolumeFraction = 0.2;
// Default TC time as a fraction of (mean diameter / initial rms speed).
inline constexpr double kDefaultTcFraction = 1e-9;

// Reads `path` (or the defaults when empty) and applies "section.key=value" overrides.
// Throws InputError.
Config load_config(const std::string& path, const std::vector<std::string>& overrides);
// Parses TOML text (used for the embedded defaults and by tests).
Config parse_config_text(std::string_view text, const std::string& source_name,
                         const std::vector<std::string>& overrides = {});

// Throws InputError for TOML text with more dotted key parts than any ballagg file needs
// (toml++ would overflow its stack on a key tens of thousands of parts deep). Called
// before every toml::parse of a user's file.
void refuse_deeply_dotted_toml(std::string_view text, const std::string& source_name);

// The values the stop criteria accept: one rule for every way of giving them, [stop] of a
// configuration file or --set, and Python's Simulation.run(clusters=, time=,
// wall_seconds=). Each throws InputError "<name> = <value>: <what is allowed>".
inline constexpr std::string_view kStopClustersAllowed = "must be an integer >= 1";
inline constexpr std::string_view kStopDurationAllowed = "must be a number > 0 (inf for no limit)";
void check_stop_clusters(std::int64_t clusters, std::string_view name);
void check_stop_duration(double value, std::string_view name);  // stop.time, stop.wall_seconds

// The box length: given, or from the lattice spacing (L = lattice_side x spacing), or from
// the volume fraction (2D: L = sqrt(N pi R^2 / Vf), 3D: L = cbrt(N 4/3 pi R^3 / Vf);
// polydisperse: L^D = sum of the sampled spheres' volumes / Vf).
double resolved_box_length(const Config& c);

// Sites per side of the smallest square (2D) or cubic (3D) lattice that holds n spheres:
// the lattice of initial.positions = "lattice" fills the box with side^D cells.
std::int64_t lattice_side(std::int64_t n, int dimension);

// The law of the generated spheres' radii is not one radius for all.
inline bool polydisperse(const SystemConfig& s) { return s.radius_distribution.law != RadiusLaw::monodisperse; }
// The mass of a generated sphere of radius r: density * sphere_volume(D, r) when
// system.density is given, else m_0 (r / R_0)^D (m_0 itself for one radius).
double sphere_mass(const SystemConfig& s, double r);

// The radii a generated start draws (initial/polydisperse_start.hpp), summarized one by
// one without a list of N radii: extremes, and the sums of volumes and masses in the order
// drawn.
struct SampledRadii {
  double smallest = 0.0, largest = 0.0;
  double volume = 0.0, mass = 0.0;
};
SampledRadii summarize_sampled_radii(const Config& c);

// The configuration as TOML text with every key (the resolved config of a run).
std::string to_toml_text(const Config& c);
// The same, as a JSON object text (for summary.json).
std::string to_json_text(const Config& c);

std::string_view to_string(RadiusLaw l);
std::string_view to_string(InitialPositions p);
std::string_view to_string(InitialVelocities v);
std::string_view to_string(EngineKind k);
std::string_view to_string(SnapshotFormat f);
std::string_view to_string(SnapshotPrecision p);

std::string_view to_string(CollisionOutcome o);
std::string_view to_string(Coagulation c);
std::string_view to_string(MergedRadius r);
std::string_view to_string(RestitutionLaw l);
std::string_view to_string(Fragmentation f);

}  // namespace ballagg
