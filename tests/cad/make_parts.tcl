# Builds the CAD test parts that need OpenCASCADE's own XDE document: colours
# on parts and faces, layers, a file in inches, an assembly whose components
# OpenCASCADE names itself. Run headless by the tests with OpenCASCADE's
# DRAW harness (Debian's occt-draw):
#
#   GONIO_CAD_OUT=DIR occt-draw -b -f tests/cad/make_parts.tcl
#
# Shapes are made in millimetres; the file is written in inches
# (write.step.unit), so the reader must convert 25.4 mm back from 1 inch.
pload ALL
set out $env(GONIO_CAD_OUT)

# A block of 1 x 2 x 3 inches, red, on layer OPTICS, with its first face
# (the x = 0 face) green; and beside it an assembly that places one small
# box twice (translated 10 and 20 mm along x).
param write.step.unit INCH
box block 25.4 50.8 76.2
explode block f
XNewDoc D
XAddShape D block
SetName D 0:1:1:1 Block
XAddSubShape D block_1 0:1:1:1
XSetColor D block 1 0 0
XSetColor D block_1 0 1 0
XSetLayer D block OPTICS
box chip 2 2 1
ttranslate chip 10 0 0
copy chip chip2
ttranslate chip2 10 0 0
compound chip chip2 pair
XAddShape D pair 1
WriteStep D $out/colours_inch.step

# The block beside construction geometry, as CAD systems export it: a wire
# of two edges as a part of its own (the reader leaves it out, warning).
param write.step.unit MM
polyline guide 0 0 0 10 0 0 10 10 0
XNewDoc W
XAddShape W block 0
SetName W 0:1:1:1 Block
XAddShape W guide 0
SetName W 0:1:1:2 Guide
WriteStep W $out/with_wire.step

# The same block written as IGES (millimetres), colour and layer kept.
param write.iges.unit MM
XNewDoc I
XAddShape I block
SetName I 0:1:1:1 Block
XSetColor I block 0 0 1
WriteIges I $out/block.igs
exit
