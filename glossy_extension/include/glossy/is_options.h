// The command-line options of the Illumination Samples extension (--algorithm is): which basis holds
// the directional distributions and how finely. Defaults are the paper's solving settings (§6,
// Table 2: eps 0.5, levels 1/3), not `glossyhr lobe`'s inspection defaults. Every bad value, and
// every option that does not belong to the chosen basis, is refused with a message naming it.
#pragma once
#include <glossy/distribution.h>
#include <hr/extension.h>

#include <string>
#include <vector>

namespace glossy {

constexpr int kMaxDirLevel = 8;  // a level-8 Haar cell spans about 0.35 degrees

/// The basis with the extension's defaults: Haar eps 0.5, levels 1 to 3; tetrahedron level 3;
/// spherical harmonics order 8.
BasisSpec defaultIsBasis();

std::vector<hr::OptionSpec> isOptionSpecs();

/// Parses the options given (names without dashes); throws hr::InputError naming the option.
BasisSpec parseIsOptions(const std::vector<hr::OptionValue>& values);

/// What the host's oracle is told of a glossy receiver's sharpness (--reflection-refine): nothing (off),
/// its lobe's width (on, the default), or the wider of the lobe and its Haar cell (cell).
enum class ReflectionRefine { Off, Lobe, Cell };

/// --reflection-refine; throws hr::InputError for a value not on/cell/off. parseIsOptions has checked
/// the names and that none is given twice.
ReflectionRefine parseReflectionRefine(const std::vector<hr::OptionValue>& values);
/// An on/off option that is on unless given as off (--sender-extent: a sender seen wider than the
/// lobe reflected as its disk, reflection.h; --exact-highlights: the display's shown light,
/// shown_light.h); throws hr::InputError for any other value.
bool parseOnOff(const std::vector<hr::OptionValue>& values, const std::string& name);

/// Checks a basis as a solution file states it; throws hr::InputError prefixed by `context`.
void validateIsBasis(const BasisSpec& b, const std::string& context);

}  // namespace glossy
