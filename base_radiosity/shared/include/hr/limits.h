// The one table of input limits, shared by the scene readers (JSON, MGF, OBJ/PLY), the solution
// reader and the command line: a value a scene may hold is exactly a value the matching flag
// accepts. The ranges keep every later stage finite and bounded: coordinates stay where Embree's
// single-precision rays are valid and still resolve centimetres, emitted power and radiance stay far
// from float overflow in images, and work (array copies, face sizes, file sizes) stays bounded.
// README.md "Limits" lists the same table.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>

namespace hr::limits {

/// A closed interval [lo, hi] of finite values; NaN is never inside.
struct Range {
  const char* name;  // the scene key, for messages
  double lo, hi;
  bool contains(double v) const { return v >= lo && v <= hi; }
  /// "[lo, hi]", written with %g so that 2147483647 and 1e-09 read naturally.
  std::string text() const;
};

// Geometry, metres. 1e6 m: a float there is spaced 0.0625 m, so rays still resolve a scene of a
// few kilometres anywhere in it; Embree itself rejects rays beyond about 1.8e18.
inline constexpr Range kCoordinate{"coordinate", -1e6, 1e6};
inline constexpr Range kLength{"length", 0.0, 1e6};           // radii, heights, sizes (> 0 where a size)
inline constexpr Range kScale{"scale", -1e6, 1e6};             // per-axis transform scale (non-zero)
inline constexpr Range kAngleDeg{"angle", -36000.0, 36000.0};  // rotations, degrees
// Radiance of an emitter, W/(m^2 sr). The sun's disk is about 2e7; 1e9 keeps radiosity (at most
// pi L_e / (1 - rho)) and pixel values many orders below float overflow.
inline constexpr Range kEmission{"emission", 0.0, 1e9};
inline constexpr Range kReflectance{"reflectance", 0.0, 1.0};
inline constexpr Range kExponent{"exponent", 0.0, 1e6};
inline constexpr Range kFovDeg{"fov_y_deg", 1e-3, 179.0};
inline constexpr Range kImageSize{"image size", 1, 16384};
// Total emitted power, W: derived from the above, checked after tessellation.
inline constexpr double kMaxPowerW = 1e30;

// Solver and renderer settings (flags and scene "settings" alike).
inline constexpr Range kEps{"eps", 1e-9, 1.0};
inline constexpr Range kMaxLevel{"max_level", 0, 20};
inline constexpr Range kMinArea{"min_area", 0.0, 1e12};
inline constexpr Range kRaysPerLink{"rays_per_link", 1, 256};
inline constexpr Range kMaxIterations{"max_iterations", 1, 100000};
inline constexpr Range kTolerance{"tolerance", 1e-12, 1.0};
inline constexpr Range kTessellation{"tessellation", 3, 1024};
inline constexpr Range kShootFraction{"shoot_fraction", 1e-6, 1.0};
inline constexpr Range kSeed{"seed", 0, 2147483647};
// A fraction of the emitted power the energy audit may find unaccounted for (command line only).
inline constexpr Range kMaxImbalance{"max_imbalance", 1e-6, 1.0};
inline constexpr Range kMemoryMb{"memory_mb", 16.0, 1e7};
inline constexpr Range kThreads{"threads", 1, 1024};
inline constexpr Range kSpp{"spp", 1, 1 << 20};
inline constexpr Range kTimeS{"time_s", 1e-3, 1e6};
inline constexpr Range kMaxDepth{"max_depth", 1, 1024};
inline constexpr Range kObjectId{"object id", 0, 4294967294.0};

// Files, bytes. Every file a scene names is read through readInputFile() with one of these.
inline constexpr std::uint64_t kMaxSceneBytes = 64ull << 20;
inline constexpr std::uint64_t kMaxMgfBytes = 256ull << 20;
inline constexpr std::uint64_t kMaxMeshBytes = 256ull << 20;
inline constexpr std::uint64_t kMaxSolutionBytes = 4ull << 30;
inline constexpr std::uint64_t kMaxImageBytes = 2ull << 30;

// Work.
inline constexpr std::uint64_t kMaxMgfWork = 10'000'000;  // entity lines evaluated, array copies included
inline constexpr std::uint64_t kMaxObjects = 1'000'000;   // scene objects (MGF entities become objects)
inline constexpr std::size_t kMaxPatches = 10'000'000;    // root patches after tessellation (~1.4 GB)
inline constexpr std::size_t kMaxFaceVertices = 1024;     // per MGF/OBJ/PLY face (ear clipping: cubic at worst)
inline constexpr std::uint64_t kMaxMeshElements = 20'000'000;  // vertices or faces one mesh file declares
inline constexpr int kMaxMgfIterate = 100000;             // xf -i N and -a N
inline constexpr int kMaxJsonDepth = 64;                  // nesting of a scene file
inline constexpr std::size_t kMaxEcho = 64;               // characters of user input quoted in a message

/// Finite and inside r.
inline bool within(double v, const Range& r) { return std::isfinite(v) && r.contains(v); }

}  // namespace hr::limits
