"""Bad-input cases: the list files (associations.txt, rgb.txt, depth.txt, groundtruth.txt) and folders."""
import shutil

from bad_inputs.registry import case, data_lines, garbage, make_dangling, make_dir, make_loop, remove, replace

# ---------------------------------------------------------------------------------------------
# 2. List files. associations.txt is used when present; the rgb.txt / depth.txt cases remove it.


def replace_line(k, new):
    """Edit: data line k (counted from 0) becomes new(old line)."""
    return lambda L, D: L[:D[k]] + [new(L[D[k]])] + L[D[k] + 1:]


def first_field(text):
    return lambda l: " ".join([text] + l.split()[1:])


TS_EDITS = {
    # name: edit(lines, data line indices) -> lines
    "garbage-line": lambda L, D: L[:D[3]] + ["!@#$ this is %% not a line &&"] + L[D[3]:],
    "one-field": replace_line(2, lambda l: l.split()[0]),
    "timestamp-nan": replace_line(1, first_field("nan")),
    "timestamp-inf": lambda L, D: replace_line(len(D) - 1, first_field("inf"))(L, D),
    "timestamp-trailing-junk": replace_line(1, lambda l: l.split()[0] + "x " + " ".join(l.split()[1:])),
    "timestamp-1000-digits": replace_line(1, first_field("9" * 1000)),
    "duplicate-line": lambda L, D: L[:D[4]] + [L[D[4]]] + L[D[4]:],
    "unsorted-lines": lambda L, D: L[:D[4]] + [L[D[5]], L[D[4]]] + L[D[5] + 1:],
    "empty": lambda L, D: [],
    "comments-only": lambda L, D: ["# nothing here", "#"],
    "utf8-bom": replace_line(0, lambda l: "\ufeff" + l),
    "nul-byte": replace_line(2, lambda l: l.replace(" ", " \0", 1)),
}
LIST_EDITS = {
    "associations.txt": ["garbage-line", "timestamp-nan", "timestamp-1000-digits", "duplicate-line",
                         "unsorted-lines", "empty", "utf8-bom", "nul-byte"],
    "rgb.txt": ["garbage-line", "timestamp-trailing-junk", "duplicate-line"],
    "depth.txt": ["one-field", "timestamp-inf", "unsorted-lines", "comments-only"],
}


def list_case(name, edit_id, edit, bug=None):
    def prepare(ctx):
        ctx.copy_seq(associations=name == "associations.txt")
        ctx.edit_lines(name, lambda L: edit(L, data_lines(L)))
        return [], name

    case(f"{name}-{edit_id}", prepare, bug)


for name, edit_ids in LIST_EDITS.items():
    for edit_id in edit_ids:
        list_case(name, edit_id, TS_EDITS[edit_id])


def list_binary(ctx):
    ctx.copy_seq()
    replace(ctx.seq / "associations.txt", garbage(3000, seed=1))
    return [], "associations.txt"


case("associations.txt-binary-garbage", list_binary)


def list_points_at(name, what):
    """The first listed image is missing / a folder / a dangling link."""

    def prepare(ctx):
        ctx.copy_seq(associations=name == "associations.txt")
        target = ctx.seq / ctx.frames[0][1 if name == "depth.txt" else 0]
        {"missing": remove, "folder": make_dir, "dangling": make_dangling}[what](target)
        return [], name

    return prepare


case("associations.txt-lists-a-missing-image", list_points_at("associations.txt", "missing"))
case("rgb.txt-lists-a-missing-image", list_points_at("rgb.txt", "missing"))
case("depth.txt-lists-a-dangling-link", list_points_at("depth.txt", "dangling"))


def no_association(ctx):
    # depth timestamps 100 s later: no colour image has a depth image within 0.02 s
    ctx.copy_seq(associations=False)

    def shift(L):
        out = []
        for l in L:
            if l.startswith("#") or not l.strip():
                out.append(l)
            else:
                t, f = l.split()
                out.append(f"{float(t) + 100:.6f} {f}")
        return out

    ctx.edit_lines("depth.txt", shift)
    return [], "rgb.txt"


case("depth.txt-no-timestamp-matches-rgb", no_association)


def list_file_is(name, what, bug=None):
    def prepare(ctx):
        ctx.copy_seq(associations=name == "associations.txt")
        p = ctx.seq / name
        {"missing": remove, "folder": make_dir, "dangling": make_dangling, "loop": make_loop}[what](p)
        if name == "associations.txt":
            # without rgb.txt / depth.txt to fall back on
            remove(ctx.seq / "rgb.txt")
            remove(ctx.seq / "depth.txt")
        return [], name

    case(f"{name}-is-{what}", prepare, bug)


list_file_is("rgb.txt", "missing")
list_file_is("depth.txt", "dangling")
list_file_is("rgb.txt", "folder")
list_file_is("associations.txt", "folder")

# groundtruth.txt is read after the run (2 frames tracked, so the trajectory can be compared).
# Unsorted lines are not an error there: TUM's evaluate_ate.py sorts them, and so does lrdslam.
GT_EDITS = {
    "garbage-line": lambda L, D: L[:D[3]] + ["garbage garbage"] + L[D[3]:],
    "infinite-value": replace_line(2, lambda l: " ".join(l.split()[:1] + ["inf"] + l.split()[2:])),
    "duplicate-line": lambda L, D: L[:D[4]] + [L[D[4]]] + L[D[4]:],
}


def gt_case(edit_id, edit):
    def prepare(ctx):
        ctx.copy_seq()
        ctx.edit_lines("groundtruth.txt", lambda L: edit(L, data_lines(L)))
        return [], "groundtruth.txt"

    case(f"groundtruth.txt-{edit_id}", prepare)


for edit_id, edit in GT_EDITS.items():
    gt_case(edit_id, edit)


def gt_folder(ctx):
    ctx.copy_seq()
    make_dir(ctx.seq / "groundtruth.txt")
    return [], "groundtruth.txt"


case("groundtruth.txt-is-a-folder", gt_folder)

# ---------------------------------------------------------------------------------------------
# 8. Folders


def seq_missing(ctx):
    ctx.sequence = ctx.tmp / "no_such_sequence"
    return [], "no_such_sequence"


def seq_empty(ctx):
    ctx.sequence = ctx.tmp / "empty_sequence"
    ctx.sequence.mkdir()
    return [], "rgb.txt"


def seq_is_file(ctx):
    ctx.sequence = replace(ctx.tmp / "sequence_file", "not a folder\n")
    return [], "sequence_file"


def rgb_folder_missing(ctx):
    ctx.copy_seq()
    remove(ctx.seq / "rgb")
    return [], "associations.txt"


def depth_folder_empty(ctx):
    ctx.copy_seq(associations=False)
    shutil.rmtree(ctx.seq / "depth")
    (ctx.seq / "depth").mkdir()
    return [], "depth.txt"


def out_is_file(ctx):
    out = replace(ctx.tmp / "out_file", "a file where the output folder should be\n")
    return ["--out", out], "out_file"


def save_masks_is_file(ctx):
    f = replace(ctx.tmp / "masks_file", "x\n")
    return ["--save-masks", f], "masks_file"


case("folder-sequence-missing", seq_missing)
case("folder-sequence-empty", seq_empty)
case("folder-sequence-is-a-file", seq_is_file)
case("folder-rgb-missing", rgb_folder_missing)
case("folder-depth-empty", depth_folder_empty)
case("folder-out-is-a-file", out_is_file)
case("folder-save-masks-is-a-file", save_masks_is_file)

