#!/usr/bin/env python3
"""Makes the hostile inputs of the hostile-input suite in a folder (python3 stdlib only).

    make_data.py BIN_DIR OUT_DIR

base/ is a clean 10-frame 160x120 sequence from df_make_sequence; every other folder is a copy
of it (files hard-linked, changed files rewritten, never edited in place) with one thing broken.
Frame 2 (stamp 1.066667, associations.txt line 3) is the frame a case breaks. Loose files
(PNG, JPEG, PLY, MCAP, configs, pipelines, trajectories) lie under files/.
"""
import os
import shutil
import struct
import subprocess
import sys
import zlib

W, H = 160, 120
FRAMES = 10
BAD = "1.066667"  # the frame cases break: associations.txt:3, rgb.txt:5, depth.txt:5


def png(width, height, bit_depth=8, colour_type=2, rows=None):
    """A valid PNG; colour_type 0 grey, 2 RGB; pixels a gradient unless rows are given."""
    channels = {0: 1, 2: 3}[colour_type]
    bpp = channels * bit_depth // 8
    if rows is None:
        raw = bytearray()
        for y in range(height):
            raw.append(0)
            for x in range(width):
                for c in range(channels):
                    v = (x * 7 + y * 3 + c * 50) % 256
                    raw += bytes([v] * (bit_depth // 8))
        rows = bytes(raw)
    assert len(rows) == height * (1 + width * bpp)

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(rows))
            + chunk(b"IEND", b""))


def png_header_only(width, height):
    """Signature and an IHDR claiming width x height, nothing else (33 bytes)."""
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + struct.pack(">I", 13) + b"IHDR" + ihdr
            + struct.pack(">I", zlib.crc32(b"IHDR" + ihdr) & 0xFFFFFFFF))


def jpeg_header(width, height, tail=b""):
    """SOI, a JFIF APP0 and a baseline SOF0 of width x height; then tail (no scan: undecodable)."""
    app0 = b"JFIF\x00\x01\x01\x00\x00\x01\x00\x01\x00\x00"
    sof = struct.pack(">BHHB", 8, height, width, 3) + b"\x01\x11\x00\x02\x11\x00\x03\x11\x00"
    return (b"\xff\xd8" + b"\xff\xe0" + struct.pack(">H", len(app0) + 2) + app0
            + b"\xff\xc0" + struct.pack(">H", len(sof) + 2) + sof + tail)


def garbage(n, seed=7):
    out = bytearray()
    x = seed
    for _ in range(n):
        x = (x * 1103515245 + 12345) & 0x7FFFFFFF
        out.append((x >> 16) & 0xFF)
    return bytes(out)


def put(path, data):
    """Writes a fresh file (unlinks first: files of a variant are hard links into base/)."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    if os.path.lexists(path):
        if os.path.isdir(path) and not os.path.islink(path):
            shutil.rmtree(path)
        else:
            os.unlink(path)
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def read(path):
    with open(path, "rb") as f:
        return f.read()


class Maker:
    def __init__(self, out):
        self.out = out
        self.base = os.path.join(out, "base")

    def variant(self, name):
        dst = os.path.join(self.out, name)
        shutil.copytree(self.base, dst, copy_function=os.link)
        return dst

    def lines(self, name, listname, edit):
        """Variant whose list file is edit(list of lines) -> list of lines (or bytes)."""
        d = self.variant(name)
        text = read(os.path.join(d, listname)).decode()
        new = edit(text.splitlines())
        put(os.path.join(d, listname), new if isinstance(new, bytes) else "\n".join(new) + "\n")
        return d


def replace_line(stamp_prefix, new):
    def edit(ls):
        return [new if l.startswith(stamp_prefix + " ") else l for l in ls]
    return edit


def ns_stamp(s):  # "1.066667" -> 19-digit integer nanoseconds text
    sec, frac = s.split(".")
    return str(int(sec) * 10**9 + int(frac.ljust(9, "0")) + 1_600_000_000 * 10**9)


def make_sequences(m):
    rgb = lambda d: os.path.join(d, "rgb", BAD + ".png")
    dep = lambda d: os.path.join(d, "depth", BAD + ".png")
    base_rgb = read(rgb(m.base))
    base_dep = read(dep(m.base))
    # Images of the broken frame.
    for name, data in [
        ("rgb_truncated", base_rgb[:100]), ("rgb_zero", b""), ("rgb_garbage", garbage(5000)),
        ("rgb_huge_header", png_header_only(16000, 16000)),
        ("rgb_max_header", png_header_only(0x7FFFFFFF, 0x7FFFFFFF)),
        ("rgb_zero_size_header", png_header_only(0, 0)),
        ("rgb_small", png(80, 60)), ("rgb_large", png(W * 2, H * 2)),
        ("rgb_16bit", png(W, H, 16, 2)), ("rgb_grey", png(W, H, 8, 0)),
        ("rgb_idat_garbage", png_header_only(W, H) + struct.pack(">I", 64) + b"IDAT"
         + garbage(68)),
        ("rgb_jpeg_truncated", jpeg_header(W, H)),
        ("rgb_jpeg_huge", jpeg_header(60000, 60000)),
        ("rgb_jpeg_wrong_size", jpeg_header(80, 60)),
        ("rgb_jpeg_bad_segment", b"\xff\xd8\xff\xe0\xff\xff" + garbage(50)),
        ("depth_truncated", base_dep[:60]), ("depth_zero", b""), ("depth_garbage", garbage(999)),
        ("depth_8bit", png(W, H, 8, 0)), ("depth_colour", png(W, H, 8, 2)),
        ("depth_small", png(80, 60, 16, 0)), ("depth_huge_header", png_header_only(20000, 20000)),
    ]:
        d = m.variant(name)
        put(dep(d) if name.startswith("depth") else rgb(d), data)
    d = m.variant("rgb_missing"); os.unlink(rgb(d))
    d = m.variant("depth_missing"); os.unlink(dep(d))
    d = m.variant("rgb_is_dir"); os.unlink(rgb(d)); os.makedirs(rgb(d))
    d = m.variant("rgb_unreadable"); put(rgb(d), base_rgb); os.chmod(rgb(d), 0)
    d = m.variant("rgb_symlink_loop"); os.unlink(rgb(d)); os.symlink(BAD + ".png", rgb(d))
    # associations.txt lines of the broken frame.
    a = "associations.txt"
    good = f"{BAD} rgb/{BAD}.png {BAD} depth/{BAD}.png"
    for name, line in [
        ("assoc_missing_fields", f"{BAD} rgb/{BAD}.png"),
        ("assoc_three_fields", f"{BAD} rgb/{BAD}.png {BAD}"),
        ("assoc_text_stamp", f"abc rgb/{BAD}.png {BAD} depth/{BAD}.png"),
        ("assoc_negative", f"-1.066667 rgb/{BAD}.png {BAD} depth/{BAD}.png"),
        ("assoc_nan", f"nan rgb/{BAD}.png nan depth/{BAD}.png"),
        ("assoc_inf", f"inf rgb/{BAD}.png inf depth/{BAD}.png"),
        ("assoc_1e300", f"1e300 rgb/{BAD}.png 1e300 depth/{BAD}.png"),
        ("assoc_exponent", f"1.066667e0 rgb/{BAD}.png {BAD} depth/{BAD}.png"),
        ("assoc_ten_decimals", f"1.0666670001 rgb/{BAD}.png {BAD} depth/{BAD}.png"),
        ("assoc_eleven_digits", f"99999999999 rgb/{BAD}.png {BAD} depth/{BAD}.png"),
        ("assoc_mixed_units", f"{ns_stamp(BAD)} rgb/{BAD}.png {ns_stamp(BAD)} depth/{BAD}.png"),
        ("assoc_far_apart", f"{BAD} rgb/{BAD}.png 9.066667 depth/{BAD}.png"),
        ("assoc_long_line", f"{BAD} rgb/{'x' * 200000}.png {BAD} depth/{BAD}.png"),
        ("assoc_binary", "\x00\x01\x02\xff\xfe garbage \x7f"),
        ("assoc_missing_image", f"{BAD} rgb/nothere.png {BAD} depth/{BAD}.png"),
        ("assoc_dotdot", f"{BAD} ../../../../../../etc/passwd {BAD} depth/{BAD}.png"),
        ("assoc_absolute_dir", f"{BAD} / {BAD} depth/{BAD}.png"),
    ]:
        m.lines(name, a, replace_line(BAD, line))
    m.lines("assoc_duplicate_stamp", a, lambda ls: ls[:3] + [ls[2]] + ls[3:])
    m.lines("assoc_unsorted", a, lambda ls: [ls[1], ls[0]] + ls[2:])
    m.lines("assoc_crlf", a, lambda ls: ("\r\n".join(ls) + "\r\n").encode())
    m.lines("assoc_bom", a, lambda ls: b"\xef\xbb\xbf" + ("\n".join(ls) + "\n").encode())
    m.lines("assoc_comments_blank", a, lambda ls: ["# c", "", "   "] + ls[:3] + ["# x", ""]
            + ls[3:])
    m.lines("assoc_only_comments", a, lambda ls: ["# nothing here"])
    m.lines("assoc_empty", a, lambda ls: b"")
    m.lines("assoc_ns_all", a, lambda ls: [" ".join(ns_stamp(f) if i % 2 == 0 else f
                                                    for i, f in enumerate(l.split()))
                                           for l in ls])
    m.lines("assoc_extra_fields", a, lambda ls: [l + " extra 42" for l in ls])
    m.lines("assoc_tabs", a, lambda ls: [l.replace(" ", "\t") for l in ls])
    # rgb.txt/depth.txt without associations.txt.
    def no_assoc(name, listname=None, edit=None):
        d = m.variant(name)
        os.unlink(os.path.join(d, a))
        if listname:
            text = read(os.path.join(d, listname)).decode()
            put(os.path.join(d, listname), "\n".join(edit(text.splitlines())) + "\n")
        return d
    no_assoc("lists_no_assoc")
    no_assoc("lists_rgb_text_stamp", "rgb.txt", replace_line(BAD, f"abc rgb/{BAD}.png"))
    no_assoc("lists_depth_nan", "depth.txt", replace_line(BAD, f"nan depth/{BAD}.png"))
    no_assoc("lists_rgb_missing_field", "rgb.txt", replace_line(BAD, BAD))
    d = no_assoc("lists_identical_ns")  # nanosecond stamps in both lists, identical per frame
    for ln in ("rgb.txt", "depth.txt"):
        text = read(os.path.join(d, ln)).decode().splitlines()
        put(os.path.join(d, ln), "\n".join(
            l if l.startswith("#") else f"{ns_stamp(l.split()[0])} {l.split()[1]}"
            for l in text) + "\n")
    d = no_assoc("lists_no_depth_txt"); os.unlink(os.path.join(d, "depth.txt"))
    d = no_assoc("lists_none"); os.unlink(os.path.join(d, "depth.txt"))
    os.unlink(os.path.join(d, "rgb.txt"))
    d = m.variant("assoc_is_dir"); os.unlink(os.path.join(d, a)); os.makedirs(os.path.join(d, a))
    d = m.variant("assoc_unreadable"); put(os.path.join(d, a), read(os.path.join(m.base, a)))
    os.chmod(os.path.join(d, a), 0)
    os.makedirs(os.path.join(m.out, "empty_folder"))
    put(os.path.join(m.out, "a_file"), "not a folder\n")
    # intrinsics.txt of the sequence.
    k = "intrinsics.txt"
    header = "# fx fy cx cy width height depth_units_per_m\n"
    for name, text in [
        ("k_fx_tiny", "1e-300 134.8 79.65 61.525 160 120 5000"),
        ("k_cx_huge", "133.85 134.8 1e300 61.525 160 120 5000"),
        ("k_fx_negative", "-133.85 134.8 79.65 61.525 160 120 5000"),
        ("k_fy_nan", "133.85 nan 79.65 61.525 160 120 5000"),
        ("k_cy_inf", "133.85 134.8 79.65 inf 160 120 5000"),
        ("k_width_wrong", "133.85 134.8 79.65 61.525 320 240 5000"),
        ("k_width_zero", "133.85 134.8 79.65 61.525 0 120 5000"),
        ("k_width_huge", "133.85 134.8 79.65 61.525 64000 120 5000"),
        ("k_width_text", "133.85 134.8 79.65 61.525 wide 120 5000"),
        ("k_width_fraction", "133.85 134.8 79.65 61.525 160.5 120 5000"),
        ("k_units_zero", "133.85 134.8 79.65 61.525 160 120 0"),
        ("k_units_negative", "133.85 134.8 79.65 61.525 160 120 -5000"),
        ("k_units_nan", "133.85 134.8 79.65 61.525 160 120 nan"),
        ("k_too_few", "133.85 134.8 79.65"),
        ("k_too_many", "133.85 134.8 79.65 61.525 160 120 5000 7 8 9"),
        ("k_empty", ""),
        ("k_only_comment", "# nothing"),
        ("k_garbage", garbage(300).decode("latin-1")),
        ("k_two_lines", "133.85 134.8 79.65 61.525 160 120 5000\n100 100 80 60 160 120 5000"),
    ]:
        d = m.variant(name)
        put(os.path.join(d, k), header + text + "\n")
    d = m.variant("k_is_dir"); os.unlink(os.path.join(d, k)); os.makedirs(os.path.join(d, k))
    # Masks for --masks (a folder of <stamp>.png, 8-bit, image size).
    def masks(name, sizes, skip=()):
        d = os.path.join(m.out, name)
        os.makedirs(d)
        for i in range(FRAMES):
            stamp = f"{1 + i / 30:.6f}"
            if stamp in skip:
                continue
            w, h = sizes(stamp)
            put(os.path.join(d, stamp + ".png"), png(w, h, 8, 0, bytes((1 + w) * h)))
        return d
    masks("masks_good", lambda s: (W, H))
    masks("masks_missing_one", lambda s: (W, H), skip=(BAD,))
    masks("masks_wrong_size", lambda s: (80, 60) if s == BAD else (W, H))
    masks("masks_all_wrong_size", lambda s: (W * 2, H * 2))
    d = masks("masks_corrupt", lambda s: (W, H)); put(os.path.join(d, BAD + ".png"), garbage(77))
    d = masks("masks_huge_header", lambda s: (W, H))
    put(os.path.join(d, BAD + ".png"), png_header_only(30000, 30000))


def make_files(m, bin_dir):
    f = os.path.join(m.out, "files")
    os.makedirs(f)
    gt = read(os.path.join(m.base, "groundtruth.txt")).decode().splitlines()
    poses = [l for l in gt if not l.startswith("#")]
    put(os.path.join(f, "gt.txt"), "\n".join(gt) + "\n")
    put(os.path.join(f, "est.txt"), "\n".join(poses) + "\n")
    def traj(name, lines):
        put(os.path.join(f, name), "\n".join(lines) + "\n")
    second = poses[2].split()
    traj("gt_text.txt", poses[:2] + ["abc " + " ".join(second[1:])] + poses[3:])
    traj("gt_short_line.txt", poses[:2] + [" ".join(second[:4])] + poses[3:])
    traj("gt_nan.txt", poses[:2] + [" ".join(second[:1] + ["nan"] + second[2:])] + poses[3:])
    traj("gt_inf_stamp.txt", poses[:2] + [" ".join(["inf"] + second[1:])] + poses[3:])
    traj("gt_1e300.txt", poses[:2] + [" ".join(["1e300"] + second[1:])] + poses[3:])
    traj("gt_zero_quat.txt", poses[:2] + [" ".join(second[:4] + ["0", "0", "0", "0"])]
         + poses[3:])
    traj("gt_big_quat.txt", poses[:2] + [" ".join(second[:4] + ["5", "0", "0", "0"])]
         + poses[3:])
    traj("gt_duplicate.txt", poses[:3] + [poses[2]] + poses[3:])
    traj("gt_unsorted.txt", [poses[1], poses[0]] + poses[2:])
    traj("gt_one_pose.txt", poses[:1])
    traj("gt_shifted.txt", [" ".join([f"{float(p.split()[0]) + 100:.6f}"] + p.split()[1:])
                            for p in poses])
    traj("gt_binary.txt", [garbage(200).decode("latin-1")])
    put(os.path.join(f, "gt_empty.txt"), "")
    put(os.path.join(f, "gt_crlf.txt"), "\r\n".join(poses) + "\r\n")
    traj("gt_eight_fields_x.txt", poses[:2] + [poses[2] + " 1"] + poses[3:])
    # PLY files.
    pts = [(x * 0.01, y * 0.01, 1.0) for x in range(20) for y in range(20)]
    def ply_ascii(points, count=None, fmt="ascii 1.0", magic="ply", end="end_header",
                  props=("x", "y", "z")):
        head = [magic, f"format {fmt}", f"element vertex {len(points) if count is None else count}"]
        head += [f"property float {p}" for p in props] + [end]
        return "\n".join(head) + "\n" + "".join(f"{x} {y} {z}\n" for x, y, z in points)
    def ply_binary(points, count=None):
        head = ("ply\nformat binary_little_endian 1.0\n"
                f"element vertex {len(points) if count is None else count}\n"
                "property float x\nproperty float y\nproperty float z\nend_header\n").encode()
        return head + b"".join(struct.pack("<fff", *p) for p in points)
    put(os.path.join(f, "good.ply"), ply_ascii(pts))
    put(os.path.join(f, "good_bin.ply"), ply_binary(pts))
    put(os.path.join(f, "ply_truncated_bin.ply"), ply_binary(pts)[:-500])
    put(os.path.join(f, "ply_truncated_ascii.ply"), ply_ascii(pts)[:-3000])
    put(os.path.join(f, "ply_no_magic.ply"), ply_ascii(pts, magic="plx"))
    put(os.path.join(f, "ply_no_end_header.ply"), ply_ascii(pts, end="end_headr"))
    put(os.path.join(f, "ply_bad_format.ply"), ply_ascii(pts, fmt="binary_middle_endian 1.0"))
    put(os.path.join(f, "ply_huge_count.ply"), ply_binary(pts, count=10**15))
    put(os.path.join(f, "ply_negative_count.ply"), ply_ascii(pts, count=-5))
    put(os.path.join(f, "ply_zero_vertices.ply"), ply_ascii([]))
    put(os.path.join(f, "ply_no_xyz.ply"), ply_ascii(pts, props=("a", "b", "c")))
    put(os.path.join(f, "ply_text_values.ply"), ply_ascii(pts).replace("0.05 ", "abc ", 3))
    put(os.path.join(f, "ply_nan_values.ply"), ply_ascii(pts).replace("0.05 ", "nan ", 3))
    put(os.path.join(f, "ply_garbage.ply"), garbage(4000))
    put(os.path.join(f, "ply_empty.ply"), b"")
    # MCAP files for df_tap play.
    magic = b"\x89MCAP0\r\n"
    header = magic + b"\x01" + struct.pack("<Q", 12) + struct.pack("<I", 4) + b"ros2" + \
        struct.pack("<I", 0)
    put(os.path.join(f, "mcap_empty.mcap"), b"")
    put(os.path.join(f, "mcap_garbage.mcap"), garbage(3000))
    put(os.path.join(f, "mcap_magic_only.mcap"), magic)
    put(os.path.join(f, "mcap_header_only.mcap"), header)
    put(os.path.join(f, "mcap_huge_record.mcap"), magic + b"\x01" + struct.pack("<Q", 2**63 - 1)
        + b"xx")
    put(os.path.join(f, "mcap_wrong_version.mcap"), b"\x89MCAP9\r\n" + header[8:] + magic)
    put(os.path.join(f, "mcap_truncated_record.mcap"), header + b"\x03" + struct.pack("<Q", 500)
        + garbage(40))
    # Configuration files.
    cfg = {
        "cfg_syntax.pbtxt": "slam { map { confidence_sigma: 0.5 }\n",
        "cfg_unknown_field.pbtxt": "no_such_option: 3\n",
        "cfg_wrong_type.pbtxt": "idle_exit_s: \"soon\"\n",
        "cfg_garbage.pbtxt": garbage(500).decode("latin-1"),
        "cfg_nested_unknown.pbtxt": "slam { map { no_such_field: 1 } }\n",
        "cfg_duplicate_scalar.pbtxt": "idle_exit_s: 1\nidle_exit_s: 2\n",
        "cfg_fusion_both.pbtxt": "classes { rigid: \"car\" non_rigid: \"car\" }\n",
        "cfg_fusion_empty_class.pbtxt": "classes { rigid: \"\" }\n",
        "cfg_detector_nms_nan.pbtxt": "model: \"simulated\"\nnms_iou_threshold: nan\n",
        "cfg_capture_rate_zero.pbtxt": "rate: 0\n",
    }
    for name, text in cfg.items():
        put(os.path.join(f, name), text)
    put(os.path.join(f, "cfg_unreadable.pbtxt"), "idle_exit_s: 1\n")
    os.chmod(os.path.join(f, "cfg_unreadable.pbtxt"), 0)
    os.makedirs(os.path.join(f, "cfg_dir.pbtxt"))
    # Pipelines for dfsup up (shared_memory false: no RouDi is looked at or started).
    svc = 'service { name: "%s" binary: "%s" %s }\n'
    pipes = {
        "pipe_unknown_binary.pbtxt": svc % ("a", "df_no_such_service", ""),
        "pipe_duplicate.pbtxt": svc % ("a", "df_geoseg", "") + svc % ("a", "df_fusion", ""),
        "pipe_syntax.pbtxt": 'service { name: "a" binary: "df_geoseg"\n',
        "pipe_missing_config.pbtxt": svc % ("a", "df_geoseg", 'config: "/nonexistent/geo.pbtxt"'),
        "pipe_reserved.pbtxt": svc % ("roudi", "df_geoseg", ""),
        "pipe_unknown_field.pbtxt": 'colour: "blue"\n',
        "pipe_no_name.pbtxt": 'service { binary: "df_geoseg" }\n',
        "pipe_probe_zero.pbtxt": "probe_period_s: 0\n" + svc % ("a", "df_geoseg", ""),
        "pipe_probe_nan.pbtxt": "probe_period_s: nan\n" + svc % ("a", "df_geoseg", ""),
        "pipe_binary_path.pbtxt": svc % ("a", "/nonexistent/bin/df_x", ""),
    }
    for name, text in pipes.items():
        put(os.path.join(f, name), "shared_memory: false\n" + text)
    # A real JPEG if the system has one (darknet's photos), truncated.
    dog = "/usr/share/darknet/data/dog.jpg"
    if os.path.exists(dog):
        put(os.path.join(f, "dog_truncated.jpg"), read(dog)[:4000])


def main():
    bin_dir, out = sys.argv[1], sys.argv[2]
    if os.path.exists(out):
        shutil.rmtree(out)
    os.makedirs(out)
    m = Maker(out)
    subprocess.run([os.path.join(bin_dir, "df_make_sequence"), "--preset", "static_xyz",
                    "--out", m.base, "--frames", str(FRAMES), "--width", str(W), "--height",
                    str(H), "--no-models", "--threads", "1"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    make_sequences(m)
    make_files(m, bin_dir)
    # Cases run as nobody (root reads anything) need to reach the data.
    for root, dirs, _ in os.walk(out):
        for x in dirs:
            os.chmod(os.path.join(root, x), 0o755)
    os.chmod(out, 0o755)


if __name__ == "__main__":
    main()
