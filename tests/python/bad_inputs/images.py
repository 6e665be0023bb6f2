"""Bad-input cases: colour and depth images, and ground-truth mask folders."""
import shutil
import zlib

import cv2
import numpy as np

from bad_inputs.registry import (case, encode_png, flip, garbage, grey_alpha_png, make_dir, make_loop, png_offset,
                                 raw_png, remove, replace)

# ---------------------------------------------------------------------------------------------
# 1. Images. Frame 0 unless the case says otherwise (frame 2 with --max-frames 3: the error comes
# while the tracker and the mapper are running).

def image_case(id_, which, corrupt, frame=0, bug=None):
    """corrupt(ctx, path, original bytes) writes the bad file."""

    def prepare(ctx):
        ctx.copy_seq()
        path = ctx.rgb(frame) if which == "rgb" else ctx.depth(frame)
        corrupt(ctx, path, ctx.read(ctx.frames[frame][0 if which == "rgb" else 1]))
        ctx.max_frames = frame + 1
        return [], path.name

    case(id_, prepare, bug)


IMAGE_CORRUPTIONS = {
    # id: (corrupt(ctx, path, original bytes), libpng complains on stderr)
    "png-empty": (lambda c, p, d: replace(p, b""), False),
    "png-truncated-half": (lambda c, p, d: replace(p, d[:len(d) // 2]), True),
    "png-bitflip-ihdr": (lambda c, p, d: replace(p, flip(d, png_offset(d, b"IHDR", 0.1), 2)), True),
    "png-bitflip-idat": (lambda c, p, d: replace(p, flip(d, png_offset(d, b"IDAT", 0.5), 5)), True),
    "png-zero-width": (lambda c, p, d: replace(p, raw_png(0, 480, 8, 0, zlib.compress(b"\0"))), True),
    "png-header-claims-100000x100000":
        (lambda c, p, d: replace(p, raw_png(100000, 100000, 8, 0, zlib.compress(b"\0" * 100001))), False),
    "random-bytes": (lambda c, p, d: replace(p, garbage(5000)), False),
    "is-a-directory": (lambda c, p, d: make_dir(p), False),
    "symlink-loop": (lambda c, p, d: make_loop(p), False),
}
RGB_SUBSET = ["png-empty", "png-truncated-half", "png-bitflip-idat", "png-zero-width",
              "png-header-claims-100000x100000", "random-bytes", "is-a-directory", "symlink-loop"]
DEPTH_SUBSET = ["png-truncated-half", "png-bitflip-ihdr", "is-a-directory"]
for id_ in RGB_SUBSET:
    image_case(f"rgb-{id_}", "rgb", IMAGE_CORRUPTIONS[id_][0])
for id_ in DEPTH_SUBSET:
    image_case(f"depth-{id_}", "depth", IMAGE_CORRUPTIONS[id_][0])

# mid-run: the third frame is bad while the map is being built
image_case("rgb-frame2-truncated", "rgb", lambda c, p, d: replace(p, d[:len(d) // 3]), frame=2)
image_case("depth-frame2-bitflip-idat", "depth",
           lambda c, p, d: replace(p, flip(d, png_offset(d, b"IDAT", 0.3), 1)), frame=2)

# wrong bit depth / channel count of the depth image (must be 16-bit single channel)
image_case("depth-8bit-grey", "depth",
           lambda c, p, d: replace(p, encode_png((c.image(c.frames[0][1]) // 256).astype(np.uint8))))
image_case("depth-16bit-3-channel", "depth",
           lambda c, p, d: replace(p, encode_png(cv2.merge([c.image(c.frames[0][1])] * 3))))
image_case("depth-16bit-grey-alpha", "depth", lambda c, p, d: replace(p, grey_alpha_png(c.image(c.frames[0][1]))))

# colour / depth size mismatch
image_case("rgb-half-size", "rgb",
           lambda c, p, d: replace(p, encode_png(cv2.resize(c.image(c.frames[0][0]), (320, 240)))))
image_case("depth-transposed", "depth",
           lambda c, p, d: replace(p, encode_png(np.ascontiguousarray(c.image(c.frames[0][1]).T))))
# 1.2 GB once decoded; the loader must reject it (here: it does not match the 640x480 depth image)
image_case("rgb-20000x20000", "rgb", lambda c, p, d: replace(p, c.big_png()))


def both_half_size(ctx):
    # colour and depth agree with each other, not with the 640x480 camera of settings.yaml
    ctx.copy_seq()
    replace(ctx.rgb(), encode_png(cv2.resize(ctx.image(ctx.frames[0][0]), (320, 240))))
    replace(ctx.depth(), encode_png(cv2.resize(ctx.image(ctx.frames[0][1]), (320, 240),
                                               interpolation=cv2.INTER_NEAREST)))
    return [], ctx.rgb().name


case("rgb-and-depth-half-size-vs-camera", both_half_size)

# ---------------------------------------------------------------------------------------------
# 7. Ground-truth mask folders (--mode semantic --segmenter gt-masks). --deterministic runs the
# segmentation in sync, so frame 0's mask is read before frame 0 is tracked; the async case reads a
# bad mask in the segmentation thread while tracking goes on.


def mask_case(id_, corrupt, bug=None, frame=0):
    def prepare(ctx):
        ctx.copy_seq(masks=True)
        target = corrupt(ctx, ctx.seq / "mask" / ctx.rgb(frame).name)
        args = ["--mode", "semantic", "--segmenter", "gt-masks"]
        if frame == 0:
            args.append("--deterministic")
        ctx.max_frames = frame + 2
        return args, target.name

    case(f"mask-{id_}", prepare, bug)


def mask_image(c, p):
    return cv2.imread(str(c.base / "mask" / p.name), cv2.IMREAD_UNCHANGED)


mask_case("folder-missing", lambda c, p: (remove(p.parent), p.parent)[1])
mask_case("folder-empty", lambda c, p: (shutil.rmtree(p.parent), p.parent.mkdir(), p.parent)[2])
mask_case("png-truncated", lambda c, p: replace(p, (c.base / "mask" / p.name).read_bytes()[:100]))
mask_case("png-16bit", lambda c, p: replace(p, encode_png(mask_image(c, p).astype(np.uint16))))
mask_case("png-half-size", lambda c, p: replace(p, encode_png(
    cv2.resize(mask_image(c, p), (320, 240), interpolation=cv2.INTER_NEAREST))))
mask_case("frame2-3-channel-async", lambda c, p: replace(p, encode_png(cv2.merge([mask_image(c, p)] * 3))), frame=2)

