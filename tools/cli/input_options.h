// The options that several subcommands share, registered on their parsers:
// how photometric files are read (tools/run/photometric_input.h), how models
// are read (tools/run/model_input.h), and the preview filter
// (tools/run/preview_output.h).
#pragma once

#include <string>

#include "photometry/diagnostics.h"
#include "sim/preview_filter.h"
#include "tools/cli/cli.h"
#include "tools/run/model_input.h"
#include "tools/run/photometric_input.h"

namespace gonio::cli {

// Registers --ldt-isym3 standard|qlumedit and --photometry ID.
void add_input_options(ArgParser& parser, InputOptions* options);

// Registers --ugr-background cie190|flux-transfer (info, report): the UGR
// table's background luminance, photometry/ugr.h.
void add_ugr_background_option(ArgParser& parser, std::string* word);
// Registers --allow-outside-paths, --no-instancing, and for CAD models
// --parts and --tessellation, on a subcommand that loads models.
void add_model_input_options(ArgParser& parser, ModelInputOptions* options);

// The preview's command-line options, as parsed.
struct PreviewOptions {
  bool enabled = false;             // --preview
  std::string filter = "bilateral"; // --filter none|bilinear|bilateral
  double threshold = 0.0;           // --threshold PHOTONS (default: per mode)
  long long levels = 0;             // --levels N (0: automatic)
  double sigma_d = 0.5;             // --sigma-d
  double sigma_r = 0.2;             // --sigma-r
  bool adaptive = false;            // --adaptive (the default)
  bool no_adaptive = false;         // --no-adaptive: the thesis's fixed threshold
};

// Registers --preview and the filter's options on a subcommand's parser.
void add_preview_options(ArgParser& parser, PreviewOptions* options);

// The filter parameters the options ask for; `parser` tells which options
// were given. Error: --adaptive with --no-adaptive.
Result<sim::PreviewFilterParams> preview_params(const PreviewOptions& options, const ArgParser& parser);

}  // namespace gonio::cli
