// IES TM-33 luminaire optical data (XML): TM-33-23 (root <IESTM33-22>,
// Version 1.1) read and written; ATLA S001 / TM-33-18 (root <IESTM33>,
// Version 1.0, the same model) and ATLA S001 / UNI 11733 (root
// <LuminaireOpticalData>) read. Beside the standard's layout, the dialect
// that other tools write (intensities as <IntensityData horz vert> directly in
// <LuminousData> or <IntensityDistribution>, spectra as wavelength and value
// lists, renamed elements; see Tm33Reader::normalise) is read, each
// rewrite named in a "tm33-dialect" info line.
//
// Reading (what each element becomes in photometry::Distribution):
// - Header: Manufacturer, CatalogNumber, Description, Laboratory,
//   ReportNumber, ReportDate and Comment become the LM-63 keywords MANUFAC,
//   LUMCAT, LUMINAIRE, TESTLAB, TEST, ISSUEDATE and OTHER; every other
//   element the standard defines there (GTIN, DocumentCreator, ...,
//   MoreInfoURI) a user keyword "_TM33_<PATH>" (the element path in upper
//   case, '/' as '_', e.g. _TM33_HEADER_GTIN), so that an IES file carries it
//   and TM-33 output gives it back.
// - Luminaire: Dimensions (metres) the luminaire body; Shape and NumEmitter
//   keywords.
// - Equipment: Gonioradiometer/Type the photometric type (CIE_ or IES_ A, B,
//   C; Gonio's angle conventions are LM-63's, which CIE's agree with for
//   Type C); everything else keywords.
// - Emitter (the first with luminous intensity data; further emitters are a
//   "tm33-emitter-ignored" warning): Quantity, Description, RatedLumens (per
//   emitter: the lamp set's flux is Quantity × RatedLumens), InputWattage
//   (per emitter, likewise), BallastFactor, TiltAngles, FixedCCT (lamp
//   colour), CIE_CRI/Ra (colour rendering), DataGeneration (the LM-63-2019
//   file generation type), LuminousData/LuminousIntensity (the intensities,
//   Multiplier applied; IntData h = C or H, v = γ or V, degrees; Symm or, if
//   absent, the range of h gives the symmetry) and SpectralData /
//   EmitterSpectral (kept as photometry::Spectrum). Other elements of the
//   standard's Emitter become keywords; radiant, photon, angular-spectral,
//   colour and illuminance data, channels and emission areas are not part of
//   Gonio's model: each is a "tm33-not-kept" warning with its line.
// - CustomData "gonio-keywords" (what Gonio writes): LM-63 keywords that
//   have no TM-33 element, restored as they were.
// - Errors name the file and line: malformed XML, another root element, a
//   missing Version/Header/Emitter or intensity block, counts that disagree
//   with the data, points missing from or repeated in the angle grid,
//   non-numbers, negative or non-finite intensities, an unknown photometric
//   type or symmetry.
//
// Writing (TM-33-23, UTF-8, numbers with up to 15 significant digits so
// intensities read back exactly) is the reverse, in the standard's layout
// (LuminousData/LuminousIntensity/IntData h v; SpectralData/EmitterSpectral/
// PwrData w), the one its published examples use: the DesignLights
// Consortium's TM-33 template and ATLA's sample document; what TM-33 cannot hold, or
// what a required element lacks, is a warning with a stable code
// ("tm33-...", listed in docs/formats.md), never dropped silently.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"

namespace gonio::io {

// The document's root: <IESTM33> (TM-33-18 / ATLA S001, Version 1.0; also
// ATLA's sample root <ATLA_S001_A>), <IESTM33-22> (TM-33-23, Version 1.1),
// <LuminaireOpticalData version="1.0"> (ATLA S001 / UNI 11733 as
// eulumdat-rs writes it).
enum class Tm33Version { Atla_S001, TM33_23, LuminaireOpticalData };

// "TM-33-18/ATLA S001" or "TM-33-23".
const char* to_string(Tm33Version version);

struct Tm33File {
  photometry::Distribution distribution;
  Tm33Version version = Tm33Version::TM33_23;
  std::vector<Finding> findings;  // format-level warnings and notes, with lines
};

// Whether the bytes are an XML document whose root element is a TM-33 one
// (<IESTM33-22>, <IESTM33>, <LuminaireOpticalData> or <ATLA_S001_A>, any
// namespace prefix), looking at the start of
// the document only.
bool looks_like_tm33(std::string_view bytes);

Result<Tm33File> parse_tm33(std::string_view bytes, const std::string& name);

// The TM-33-23 document of `d`. Warnings (what TM-33 cannot hold, required
// elements written as "not stated") are appended to `warnings` if not null.
std::string write_tm33(const photometry::Distribution& d, std::vector<Finding>* warnings);

}  // namespace gonio::io
