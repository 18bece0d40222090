"""`import oitref` checked against independent computations: the command-line program's bits,
numpy's IEEE half floats, exact rational rounding, and the reference manifest's frame hashes."""
import hashlib
import json
import os
import subprocess
from fractions import Fraction

import numpy as np
import pytest

import oitref

SOURCE = os.environ["OITREF_SOURCE_DIR"]
CLI = os.environ["OITREF_CLI"]
OVER = "src_alpha,one_minus_src_alpha,one,one_minus_src_alpha"


def manifest():
    hashes = {}
    with open(os.path.join(SOURCE, "reference", "manifest.txt")) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                scene, method, digest = line.split()
                hashes[(scene, method)] = digest
    return hashes


FORMATS = ["rgba16f", "rgba8", "r11g11b10f", "rgb10a2", "rgba32f", "r16f", "rg8"]
STATES = [("add", OVER), ("add", "one,one"), ("add", "zero,one_minus_src_color"), ("max", "one,one"),
          ("reverse_subtract", "dst_alpha,one,zero,one_minus_src_alpha")]


@pytest.mark.parametrize("profile", ["exact", "llvmpipe", "nvidia"])
def test_blend_gives_the_command_lines_bits(profile, tmp_path):
    rng = np.random.default_rng(7)
    src = rng.uniform(-0.25, 1.5, (8, 4)).astype(np.float32)
    dst = rng.uniform(0.0, 1.0, (8, 4)).astype(np.float32)
    rows, ours = [], []
    for fmt in FORMATS:
        for equation, func in STATES:
            bits, values = oitref.blend(fmt, src, dst, equation=equation, func=func, profile=profile)
            assert values.shape == (8, 4) and values.dtype == np.float32
            assert np.array_equal(oitref.decode(fmt, bits), values)
            f = func.split(",")
            f = f if len(f) == 4 else f * 2
            for i in range(8):
                rows.append(",".join([fmt, equation, equation, *f, "0", "0", "0", "0",
                                      *map(repr, dst[i].tolist()), *map(repr, src[i].tolist())]))
                ours.append(bits[i].tobytes())
    cases = tmp_path / "cases.csv"
    header = ("format,eq_rgb,eq_alpha,src_rgb,dst_rgb,src_alpha,dst_alpha,const_r,const_g,const_b,const_a,"
              "dst_r,dst_g,dst_b,dst_a,src_r,src_g,src_b,src_a")
    cases.write_text(header + "\n" + "\n".join(rows) + "\n")
    out = subprocess.run([CLI, "blend", "--cases", str(cases), "--profile", profile], check=True,
                         capture_output=True, text=True).stdout.splitlines()
    columns = out[0].split(",")
    assert len(out) == len(rows) + 1
    for line, texel in zip(out[1:], ours):
        fields = dict(zip(columns, line.split(",")))
        expected = fields["result_bits"]
        words = len(expected.split())
        packed = fields["format"] in ("r11g11b10f", "rgb10a2")
        got = ("%08x" % int.from_bytes(texel, "little")) if packed else \
            " ".join("%0*x" % (2 * (len(texel) // words), int.from_bytes(texel[k * len(texel) // words:(k + 1) * len(texel) // words], "little"))
                     for k in range(words))
        assert got == expected, line


def test_rgba16f_encoding_is_numpys_half_in_the_exact_profile():
    values = np.random.default_rng(1).normal(0.0, 3000.0, (1000, 4)).astype(np.float32)
    values[:8] = [[np.inf, -np.inf, 0.0, -0.0], [65520.0, 65519.0, 6e-8, -3e-8],
                  [1.0 + 2**-11, 1.0 + 3 * 2**-11, 2**-25, 2**-24], [0.1, 0.2, 0.3, 0.4],
                  [1e6, -1e6, 5.96e-8, 2.9802322e-08], [1, 2, 3, 4], [-1, -2, -3, -4], [0.5, 0.25, 0.125, 0.0625]]
    bits = oitref.encode("rgba16f", values, "exact")
    with np.errstate(over="ignore"):  # numpy's cast to half overflows to inf, as the exact profile does
        half = values.astype(np.float16)
    assert np.array_equal(bits.view("<u2"), half.view("<u2"))
    assert np.array_equal(oitref.decode("rgba16f", bits), half.astype(np.float32))


def test_rgba8_encoding_rounds_the_exact_value_to_nearest_even():
    values = np.random.default_rng(2).uniform(-0.1, 1.1, (500, 4)).astype(np.float32)
    values[0] = [0.5 / 255, 1.5 / 255, 2.5 / 255, 254.5 / 255]
    bits = oitref.encode("rgba8", values, "exact")
    expected = [[round(min(max(Fraction(float(v)), Fraction(0)), Fraction(1)) * 255) for v in row] for row in values]
    assert bits.tolist() == expected


def frame_hash(frame):
    # The frame's bits as oitref stores them: rows bottom first, RGBA8 then RGBA32F.
    return hashlib.sha256(frame["final8"][::-1].tobytes() +
                          frame["image"][::-1].astype("<f4").tobytes()).hexdigest()


@pytest.mark.parametrize("scene,method", [("glass", "wboit"), ("squares", "abuffer"), ("veils", "mboit")])
def test_render_gives_the_manifests_bits(scene, method):
    frame = oitref.render(os.path.join(SOURCE, "scenes", scene + ".json"), method, size=(96, 72), threads=2)
    assert frame["image"].shape == (72, 96, 4) and frame["final8"].shape == (72, 96, 4)
    assert frame["sha256"] == manifest()[(scene, method)]
    assert frame_hash(frame) == frame["sha256"]
    opaque = frame["attachments"]["opaque"]
    assert opaque["format"] == "rgba8" and np.array_equal(opaque["bits"], frame["final8"])


def test_render_takes_the_scene_as_a_dict_and_reports_stats():
    with open(os.path.join(SOURCE, "scenes", "squares.json")) as f:
        scene = json.load(f)
    folder = os.path.join(SOURCE, "scenes")
    frame = oitref.render(scene, "abuffer", size=(96, 72), threads=1, folder=folder)
    assert frame["sha256"] == manifest()[("squares", "abuffer")]
    stats = frame["stats"]
    assert stats["fragments"] > 0 and stats["depth_complexity_max"] >= 1
    peel = oitref.render(scene, "peel", {"passes": "2"}, size=(96, 72), threads=1, folder=folder)
    assert peel["stats"]["peeling_passes"] == 2
    assert peel["stats"]["layers_peeled"] == 2 and peel["stats"]["all_layers_peeled"] is False


def test_compare_against_closed_forms():
    # Multiples of 2^-10 in [0, 1): adding 1/8 to them is exact in float32.
    a = (np.random.default_rng(3).integers(0, 1024, (16, 24, 4)) / 1024).astype(np.float32)
    same = oitref.compare(a, a)
    assert same["rmse"] == 0 and same["max_abs"] == 0 and same["flip"] == 0
    shifted = a.copy()
    shifted[..., :3] += np.float32(0.125)  # every colour channel off by exactly 1/8
    d = oitref.compare(a, shifted)
    assert d["max_abs"] == 0.125 and d["pixels"] == 16 * 24 and d["pixels_above"] == 16 * 24
    assert d["rmse"] == pytest.approx(0.125, rel=1e-12)


def test_bad_input_raises_value_errors_that_say_what():
    with pytest.raises(ValueError, match="rgba17f"):
        oitref.encode("rgba17f", np.zeros((1, 4), np.float32))
    with pytest.raises(ValueError, match="last axis"):
        oitref.decode("rgba16f", np.zeros((3, 5), np.uint8))
    with pytest.raises(ValueError, match="nosuch"):
        oitref.blend("rgba8", np.zeros((1, 4)), np.zeros((1, 4)), func="nosuch,one")
    with pytest.raises(ValueError, match="nosuch"):
        oitref.render(os.path.join(SOURCE, "scenes", "squares.json"), "nosuch")
    with pytest.raises(RuntimeError, match="nothing.json"):
        oitref.render(os.path.join(SOURCE, "scenes", "nothing.json"))
    with open(os.path.join(SOURCE, "scenes", "squares.json")) as f:
        scene = json.load(f)
    with pytest.raises(RuntimeError, match=r"objects\[0\]\.file_path"):  # its meshes are not in this folder
        oitref.render(scene, folder=os.path.join(SOURCE, "reference"))


@pytest.mark.parametrize("method,options", [("peel", {"passes": "2"}), ("abuffer", {}), ("mboit", {})])
def test_the_command_lines_json_reports_the_same_frame(method, options):
    path = os.path.join(SOURCE, "scenes", "squares.json")
    args = [CLI, "render", path, "--method", method, "--size", "96x72", "--threads", "1", "--json"]
    for key, value in options.items():
        args += ["--set", "%s=%s" % (key, value)]
    cli = json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
    frame = oitref.render(path, method, options, size=(96, 72), threads=1)
    assert cli["sha256"] == frame["sha256"]
    assert cli["stats"].keys() == frame["stats"].keys()
    for key, value in frame["stats"].items():
        assert cli["stats"][key] == (pytest.approx(value, rel=1e-8) if isinstance(value, float) else value), key
