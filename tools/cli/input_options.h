// The options that several subcommands share, registered on their parsers:
// how photometric files are read (tools/run/photometric_input.h), how models
// are read (tools/run/model_input.h), and the preview filter
// (tools/run/preview_output.h): what they ask for goes into the
// application's plain option structs.
#pragma once

#include <string>

#include "photometry/diagnostics.h"
#include "tools/cli/cli.h"
#include "tools/run/model_input.h"
#include "tools/run/photometric_input.h"
#include "tools/run/preview_output.h"

namespace gonio::cli {

// Registers --ldt-isym3 standard|qlumedit and --photometry ID.
void add_input_options(ArgParser& parser, app::InputOptions* options);

// Registers --ugr-background cie190|flux-transfer (info, report): the UGR
// table's background luminance, photometry/ugr.h.
void add_ugr_background_option(ArgParser& parser, std::string* word);
// Registers --allow-outside-paths, --no-instancing, and for CAD models
// --parts and --tessellation, on a subcommand that loads models.
void add_model_input_options(ArgParser& parser, app::ModelInputOptions* options);

// Registers --preview and the filter's options (tools/run/preview_output.h)
// on a subcommand's parser.
void add_preview_options(ArgParser& parser, app::PreviewOptions* options);

}  // namespace gonio::cli
