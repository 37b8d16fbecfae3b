// How subcommands read measured photometric files (.ies, .ldt): the options
// they share and the reporting of what the readers found.
#pragma once

#include <string>
#include <vector>

#include "io/photometric/photometric_file.h"
#include "photometry/ugr.h"
#include "tools/run/console.h"

namespace gonio::cli {

// The words of --ldt-isym3 and --ldt-isym3-out.
inline constexpr const char* kIsym3Standard = "standard";  // C270 … C0 … C90 (the standard)
inline constexpr const char* kIsym3QLumEdit = "qlumedit";  // C90 … C180 … C270 (QLumEdit)

struct InputOptions {
  std::string ldt_isym3 = kIsym3Standard;
  std::string gldf_photometry;  // --photometry ID: which photometry of a GLDF
};

io::LdtIsym3Order isym3_order(const std::string& word);

// The UGR options of a word of that choice.
photometry::UgrOptions ugr_options(const std::string& word);
io::PhotometricReadOptions read_options(const InputOptions& options);

// Reads a file and prints the reader's warnings (and, with `print_info`, its
// notes) to stderr (print_finding); on failure prints the error and returns it.
Result<io::PhotometricFile> read_input(const std::string& path, const InputOptions& options,
                                       bool print_info = true);

// Every photometry of a file (several for a GLDF container), likewise.
Result<std::vector<io::PhotometricFile>> read_inputs(const std::string& path, const InputOptions& options,
                                                     bool print_info = true);

}  // namespace gonio::cli
