# Builds the CAD test parts with FreeCAD, run headless by the tests:
#
#   freecadcmd tests/cad/make_parts.py            (the folder from $GONIO_CAD_OUT)
#
# FreeCAD writes STEP through its own assembly export (Import.export: App::Part
# containers become STEP assemblies, App::Link copies share one product) and,
# for the plain and IGES files, through OpenCASCADE's writers directly
# (Shape.exportStep, Shape.exportIges). Dimensions in millimetres; every
# number here is one the tests check against a closed form
# (tests/io/model/cad_test.cpp).
import math
import os
import sys

import FreeCAD
import Import
import Part
from FreeCAD import Matrix, Placement, Rotation, Vector

out = os.environ.get("GONIO_CAD_OUT") or (sys.argv[-1] if len(sys.argv) > 1 else ".")
os.makedirs(out, exist_ok=True)

F = 10.0        # the reflector's focal length [mm]
R_HOLE = 4.0    # the radius of its lamp hole [mm]
R_APER = 30.0   # its aperture radius [mm]
BALL_R = 5.0    # the ball lens's radius [mm]


def paraboloid(f, r0, r1):
    """A paraboloid reflector face with its focus at the origin, opening
    towards -Z (z = f - r^2/(4f)): light from the focus leaves along -Z."""
    p = Part.Parabola()
    p.Focal = f
    # Geom_Parabola: P(u) = (u^2/(4f), u, 0); map x -> -z + f, y -> x.
    # transformShape keeps the exact parabola (transformGeometry would
    # approximate it by a B-spline, whose normals are off by ~0.02°).
    edge = p.toShape(r0, r1)
    edge.transformShape(Matrix(0, 1, 0, 0,
                               0, 0, -1, 0,
                               -1, 0, 0, f,
                               0, 0, 0, 1))
    return edge.revolve(Vector(0, 0, 0), Vector(0, 0, 1), 360)


def plano_convex(radius, diameter, thickness):
    """A plano-convex lens: flat face at z = thickness facing +Z, convex face
    through the origin facing -Z (sphere centre (0, 0, radius))."""
    sphere = Part.makeSphere(radius, Vector(0, 0, radius))
    slab = Part.makeCylinder(diameter / 2, thickness, Vector(0, 0, 0), Vector(0, 0, 1))
    return sphere.common(slab)


def export(objects, name):
    Import.export(objects, os.path.join(out, name))


doc = FreeCAD.newDocument("parts")


def feature(name, shape):
    o = doc.addObject("Part::Feature", name)
    o.Shape = shape
    return o


reflector = feature("Reflector", paraboloid(F, R_HOLE, R_APER))
ball = feature("BallLens", Part.makeSphere(BALL_R))
pcx = feature("Lens", plano_convex(20.6, 24.0, 4.5))
doc.recompute()
export([reflector], "reflector.step")
export([ball], "ball_lens.step")
export([pcx], "pcx_lens.step")

# A luminaire assembly: a housing, the reflector, three copies of one LED
# (App::Link: one product placed three times) and the lens, in a container.
lamp = doc.addObject("App::Part", "Lamp")
housing = feature("Housing", Part.makeBox(80, 80, 5, Vector(-40, -40, 12)))
led = feature("LED", Part.makeBox(2, 2, 1, Vector(-1, -1, 0)))
lamp.addObject(housing)
lamp.addObject(reflector)
for i in range(3):
    link = doc.addObject("App::Link", "LED%d" % (i + 1))
    link.LinkedObject = led
    link.Placement = Placement(Vector(3.0 * (i - 1), 0, 0.5), Rotation(Vector(0, 0, 1), 90 * i))
    lamp.addObject(link)
lens_link = doc.addObject("App::Link", "FrontLens")
lens_link.LinkedObject = pcx
lens_link.Placement = Placement(Vector(0, 0, -40), Rotation())
lamp.addObject(lens_link)
doc.recompute()
export([lamp], "lamp.step")

# Placements that are not their own transpose (issue 45): a bar of
# 10 x 2 x 1 mm from the origin (no symmetry to hide a rotation's sense)
# placed three times, turned 90 deg about X, 30 deg about Y and 90 deg about
# Z, and once more in a two-level assembly whose middle level (Arm) is
# itself turned and moved: the tests know where each corner lands.
bar = feature("Bar", Part.makeBox(10, 2, 1))
turned = doc.addObject("App::Part", "Turned")


def placed_link(name, target, placement):
    link = doc.addObject("App::Link", name)
    link.LinkedObject = target
    link.Placement = placement
    return link


turned.addObject(placed_link("BarX90", bar, Placement(Vector(20, 0, 0), Rotation(Vector(1, 0, 0), 90))))
turned.addObject(placed_link("BarY30", bar, Placement(Vector(0, 20, 0), Rotation(Vector(0, 1, 0), 30))))
turned.addObject(placed_link("BarZ90", bar, Placement(Vector(0, 0, 20), Rotation(Vector(0, 0, 1), 90))))
arm = doc.addObject("App::Part", "Arm")
arm.Placement = Placement(Vector(40, 0, 0), Rotation(Vector(0, 0, 1), 90))
arm.addObject(placed_link("Tip", bar, Placement(Vector(0, 10, 0), Rotation(Vector(1, 0, 0), 90))))
turned.addObject(arm)
doc.recompute()
export([turned], "turned.step")

# A flat square of 10 x 10 mm in z = 0, facing +Z: an emissive panel of
# known area.
panel = feature("Panel", Part.makePlane(10, 10))
doc.recompute()
export([panel], "panel.step")

# The reflector with its face written reversed (ADVANCED_FACE's same_sense
# .F.: OpenCASCADE reads the face REVERSED), the same surface otherwise.
reversed_reflector = feature("ReflectorReversed", paraboloid(F, R_HOLE, R_APER).reversed())
doc.recompute()
export([reversed_reflector], "reflector_reversed.step")

# A lens whose surfaces do not close: half a sphere's surface, no cap.
half = Part.makeSphere(BALL_R, Vector(0, 0, 0), Vector(0, 0, 1), 0, 90).Faces[0]
export([feature("OpenLens", Part.Shell([half]))], "open_lens.step")

# OpenCASCADE's own writers, without FreeCAD's document: a plain STEP of
# the ball (no product name but the writer's) and an IGES of the lens.
Part.makeSphere(BALL_R).exportStep(os.path.join(out, "ball_plain.step"))
plano_convex(20.6, 24.0, 4.5).exportIges(os.path.join(out, "pcx_lens.igs"))

# With GONIO_CAD_LARGE=1 (benchmarks/cad_setup_study.cpp): a lens array of 16
# spheres of different radii (distinct parts, nothing to instance), about
# 10^6 triangles at the default tessellation.
if os.environ.get("GONIO_CAD_LARGE") == "1":
    array = doc.addObject("App::Part", "LensArray")
    for i in range(16):
        r = 4.0 + 0.15 * i
        lens = feature("Lens%02d" % i, Part.makeSphere(r, Vector(15.0 * (i % 4), 15.0 * (i // 4), 0)))
        array.addObject(lens)
    doc.recompute()
    export([array], "lens_array.step")

print("gonio: CAD test parts written to " + out)
