"""gonio.Model: a luminaire built in memory from numpy arrays and the CAD
sidecar's dicts, traced by gonio.simulate without writing a file (ctest
label `python`)."""
import base64
import json

import numpy as np
import pytest

import gonio

RUN = dict(photons=20000, iterations=1, seed=3, threads=1, gamma_step=2.5)


def paraboloid(focal=0.02, rho_max=0.03, rings=12, sectors=24):
    """A paraboloid dish in glTF's axes (Y up), its focus at the origin,
    opening downward (−Y): vertices [m], triangles counter-clockwise seen
    from the focus (inside), and its exact unit normals toward the focus's
    side (a coarse mesh: with them the beam is collimated, without them not)."""
    verts, normals = [], []
    for i in range(rings + 1):
        rho = 0.004 + (rho_max - 0.004) * i / rings
        y = focal - rho * rho / (4 * focal)
        for j in range(sectors):
            a = 2 * np.pi * j / sectors
            verts.append((rho * np.cos(a), y, rho * np.sin(a)))
            n = np.array([-rho * np.cos(a) / (2 * focal), -1.0, -rho * np.sin(a) / (2 * focal)])
            normals.append(n / np.linalg.norm(n))
    tris = []
    for i in range(rings):
        for j in range(sectors):
            a, b = i * sectors + j, i * sectors + (j + 1) % sectors
            c, d = a + sectors, b + sectors
            tris += [(a, d, b), (a, c, d)]
    return np.array(verts), np.array(tris, dtype=np.int64), np.array(normals)


def write_gltf(path, verts, tris, normals, flux_lm):
    """The same dish as a glTF file: float32 positions and normals, uint32
    indices in a data URI, the material's keys as extras.gonio, an isotropic
    point light (KHR_lights_punctual) at the origin with its flux."""
    pos = verts.astype(np.float32).tobytes()
    nor = normals.astype(np.float32).tobytes()
    idx = tris.astype(np.uint32).tobytes()
    blob = pos + nor + idx
    n = len(verts)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "dish", "mesh": 0},
                  {"name": "LED", "extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "intensity": flux_lm / (4 * np.pi), "extras": {"gonio": {"flux_lm": flux_lm}}}]}},
        "materials": [{"name": "mirror", "extras": {"gonio": {"mirror": 0.9}}}],
        "meshes": [{"name": "dish", "primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
                        {"buffer": 0, "byteOffset": len(pos), "byteLength": len(nor)},
                        {"buffer": 0, "byteOffset": len(pos) + len(nor), "byteLength": len(idx)}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
             "min": verts.min(axis=0).astype(np.float32).tolist(), "max": verts.max(axis=0).astype(np.float32).tolist()},
            {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": tris.size, "type": "SCALAR"}],
    }
    path.write_text(json.dumps(doc))


def dish_model(verts, tris, normals, flux_lm):
    """The dish in memory, in glTF's frame (up +Y, C0 +X, metres) so that
    its world is the glTF file's; the light's axes as glTF's (nadir −Z, C0 +X)."""
    model = gonio.Model(length_unit="m", frame={"up": [0, 1, 0], "c0": [1, 0, 0]}, name="dish")
    model.material("mirror", {"mirror": 0.9})
    model.add_mesh("dish", verts, tris, normals=normals, material="mirror")
    model.add_emitter({"name": "LED", "position": [0, 0, 0], "nadir": [0, 0, -1], "c0": [1, 0, 0],
                       "flux_lm": flux_lm})
    return model


def test_model_from_arrays_traces_as_the_same_gltf(tmp_path):
    verts, tris, normals = paraboloid()
    write_gltf(tmp_path / "dish.gltf", verts, tris, normals, 1000.0)
    from_file = gonio.simulate(tmp_path / "dish.gltf", **RUN)
    in_memory = gonio.simulate(dish_model(verts, tris, normals, 1000.0), **RUN)
    # The same candela, byte for byte, and the same ledger.
    assert from_file.photometry.candela.tobytes() == in_memory.photometry.candela.tobytes()
    assert from_file.ledger["escaped"] == in_memory.ledger["escaped"]
    assert from_file.ledger["absorbed"] == in_memory.ledger["absorbed"]
    # The mirror does something: light is absorbed (10 % of what it reflects).
    assert in_memory.ledger["absorbed"]["flux_lm"] > 1.0
    # Nothing was written where the script runs.
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dish.gltf"]
    # The normals are used: without them (the faces' own) the beam is another.
    flat = gonio.Model(length_unit="m", frame={"up": [0, 1, 0], "c0": [1, 0, 0]}, name="dish")
    flat.material("mirror", {"mirror": 0.9})
    flat.add_mesh("dish", verts, tris, material="mirror")
    flat.add_emitter({"name": "LED", "position": [0, 0, 0], "nadir": [0, 0, -1], "c0": [1, 0, 0], "flux_lm": 1000.0})
    assert gonio.simulate(flat, **RUN).photometry.candela.tobytes() != in_memory.photometry.candela.tobytes()
    # Another mirror reflectance in memory gives other candela (the material is read).
    other = dish_model(verts, tris, normals, 1000.0)
    other.material("mirror", {"mirror": 0.5})
    assert gonio.simulate(other, **RUN).photometry.candela.tobytes() != in_memory.photometry.candela.tobytes()


def test_bad_arrays_raise_naming_the_argument():
    verts, tris, normals = paraboloid(rings=2, sectors=6)
    model = gonio.Model()
    model.material("m", {"mirror": 1.0})
    bad = [
        (dict(vertices=verts[:, :2]), "vertices"),
        (dict(vertices=np.where(np.arange(verts.size).reshape(verts.shape) == 4, np.nan, verts)), "vertices"),
        (dict(vertices="not an array"), "vertices"),
        (dict(triangles=tris[:, :2]), "triangles"),
        (dict(triangles=np.where(tris == tris.max(), len(verts), tris)), "triangles"),
        (dict(triangles=-tris), "triangles"),
        (dict(triangles=tris.astype(float)), "triangles"),
        (dict(normals=normals[:-1]), "normals"),
        (dict(normals=np.full_like(normals, np.inf)), "normals"),
        (dict(normals=np.zeros_like(normals)), "normals"),
    ]
    for change, name in bad:
        args = dict(vertices=verts, triangles=tris, normals=normals)
        args.update(change)
        with pytest.raises(ValueError, match=f"^{name}:"):
            model.add_mesh("dish", args["vertices"], args["triangles"], normals=args["normals"], material="m")
    assert model.meshes == []  # nothing half added
    model.add_mesh("dish", verts, tris, material="m")
    with pytest.raises(ValueError, match="^name:"):
        model.add_mesh("dish", verts, tris, material="m")
    with pytest.raises(ValueError, match="^length_unit:"):
        gonio.Model(length_unit="furlong")


def test_bad_materials_and_emitters_raise():
    verts, tris, _ = paraboloid(rings=2, sectors=6)
    model = gonio.Model()
    model.add_mesh("dish", verts * 1000, tris, material="missing")
    with pytest.raises(ValueError, match="emitter"):
        gonio.simulate(model, **RUN)
    model.add_emitter({"name": "LED", "position": [0, 0, 0], "flux_lm": 100})
    with pytest.raises(ValueError, match="material: mesh 'dish' names material 'missing'"):
        gonio.simulate(model, **RUN)
    model.material("missing", {"colour_of_the_sky": 1})
    with pytest.raises(gonio.GonioError, match="material 'missing': says neither how it scatters"):
        gonio.simulate(model, **RUN)
    model.material("missing", {"mirror": 1.0})
    model.add_emitter({"name": "LED2", "position": [0, 0, 0], "flux": 100})
    with pytest.raises(gonio.GonioError, match="flux"):
        gonio.simulate(model, **RUN)
