#include "tools/cli/input_options.h"

namespace gonio::cli {

void add_input_options(ArgParser& parser, app::InputOptions* options) {
  parser.choice("ldt-isym3", &options->ldt_isym3, {app::kIsym3Standard, app::kIsym3QLumEdit},
                "Plane order of EULUMDAT input with Isym 3 (C90-C270 symmetry): 'standard' "
                "stores C270 ... C0 ... C90 as the standard defines; 'qlumedit' stores "
                "C90 ... C180 ... C270 as QLumEdit writes it (a half turn of the other). No "
                "field in the file tells them apart. Default: standard.");
  parser.option("photometry", &options->gldf_photometry, "ID",
                "Of a GLDF container, the photometry to read: its id in product.xml or its file "
                "(ldc/NAME). Default: every one where the command reports several (info, check), "
                "else the first.");
}

void add_ugr_background_option(ArgParser& parser, std::string* word) {
  parser.choice("ugr-background", word,
                {photometry::to_string(photometry::UgrBackground::Cie190),
                 photometry::to_string(photometry::UgrBackground::FluxTransfer)},
                "Background luminance of the UGR table: 'cie190' as CIE 190:2010 eq. 7-12 with its "
                "Tables 4 and 5 (what DIALux, Relux and the CIE's example use; default), or "
                "'flux-transfer', Gonio's own inter-reflection model of each room (docs/methods.md "
                "\"Light-planning figures\" says when they differ).");
}

void add_model_input_options(ArgParser& parser, app::ModelInputOptions* options) {
  parser.flag("allow-outside-paths", &options->allow_outside_paths,
              "let the model's uris (buffers, images, light profiles), or a CAD sidecar's profiles and "
              "ray files, name files outside its folder (absolute paths, '..', symbolic links leading "
              "out); refused by default");
  parser.flag("no-instancing", &options->no_instancing,
              "store a mesh that several nodes (or EXT_mesh_gpu_instancing, or a CAD assembly) place, "
              "once per copy as world geometry instead of once with Embree instances: same results "
              "within photon noise, more memory and setup time (for comparisons)");
  parser.option("parts", &options->parts_file, "FILE",
                "CAD models (.step, .stp, .iges, .igs): the sidecar that gives their parts materials and "
                "places the emitters (TOML, docs/cad.md; default: MODEL's name with .gonio.toml, beside it)");
  parser.option("tessellation", &options->tessellation, "DEG[,MM]",
                "CAD models: mesh each part so that no facet's normal is more than DEG degrees off the "
                "surface's, shading with the exact surface's normals (default: 0.8 x the gamma step, 2 on "
                "the default grid); DEG,MM instead meshes every part once to MM millimetres from the "
                "surface, DEG then bounding the facets along edges only (docs/cad.md; meshes are cached)");
}

void add_preview_options(ArgParser& parser, app::PreviewOptions* o) {
  parser.flag("preview", &o->enabled,
              "After every iteration write the filtered preview as DIR/preview.exr and an "
              "unfolded, tone-mapped cube as DIR/preview.png.");
  parser.choice("filter", &o->filter, {"none", "bilinear", "bilateral"},
                "Preview interpolation (default bilateral).");
  parser.option("threshold", &o->threshold, app::kThresholdBounds.min, app::kThresholdBounds.max, "PHOTONS",
                "A texel with more photons is stable (default 6400 adaptive, 100 with --no-adaptive).");
  parser.option("levels", &o->levels, app::kLevelsBounds.min, app::kLevelsBounds.max, "N",
                "Pyramid levels in use, level 0 included (default 0: down to faces of 16 texels).");
  parser.option("sigma-d", &o->sigma_d, app::kSigmaBounds.min, app::kSigmaBounds.max, "S",
                "Bilateral closeness sigma, in coarse texels (default 0.5).");
  parser.option("sigma-r", &o->sigma_r, app::kSigmaBounds.min, app::kSigmaBounds.max, "S",
                "Bilateral range sigma, relative to the brightest coarse texel (default 0.2).");
  parser.flag("adaptive", &o->adaptive,
              "Adaptive stability (the default): below the threshold a texel is kept where its "
              "photons contradict the smoothed estimate by more than 3.5 sigma.");
  parser.flag("no-adaptive", &o->no_adaptive, "The reference thesis's fixed threshold only.");
}

}  // namespace gonio::cli
