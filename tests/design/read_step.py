# Opens a STEP file with FreeCAD, run headless by tests/design/design_step_test.cpp:
#
#   GONIO_STEP_IN=x.step GONIO_STEP_OUT=parts.txt freecadcmd tests/design/read_step.py
#
# Writes one line per object FreeCAD made of it that has a shape: its label,
# its type (Part::Feature a part, App::Part an assembly), the shape's surface
# area [mm²] and its number of faces, separated by tabs. Import.open, not
# Import.insert: FreeCAD 0.20's insert into a new document ends with SIGSEGV
# on a STEP assembly of two or more parts when run headless.
import os

import FreeCAD
import Import

Import.open(os.environ["GONIO_STEP_IN"])
doc = FreeCAD.ActiveDocument
with open(os.environ["GONIO_STEP_OUT"], "w", encoding="utf-8") as out:
    for o in doc.Objects:
        shape = getattr(o, "Shape", None)
        if shape is None or shape.isNull() or len(shape.Faces) == 0:
            continue
        out.write("%s\t%s\t%.12g\t%d\n" % (o.Label, o.TypeId, shape.Area, len(shape.Faces)))
