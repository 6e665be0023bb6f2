"""FNet (training/fnet): Ghost module, unpooling equivalence, shapes, params, training step, VOC reader,
ONNX export equivalence in OpenCV DNN. Tiny inputs and fnet-lite keep this well under 90 s on 2 cores."""
import os
import sys
import warnings

import numpy as np
import pytest

torch = pytest.importorskip("torch", reason="python3-torch not installed (scripts/install-deps.sh)")
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, ROOT)

import torch.nn.functional as F  # noqa: E402

from training.fnet import ghost, unpool  # noqa: E402
from training.fnet.model import Deconv, build_model, count_params, upsample_logits  # noqa: E402

torch.set_num_threads(1)


def test_ghost_module_channels_and_param_formula():
    for cin, cout, k, s, d in [(16, 32, 1, 2, 3), (8, 64, 3, 3, 3), (3, 64, 7, 2, 3), (12, 20, 3, 4, 5), (6, 8, 1, 1, 3)]:
        m = ghost.GhostModule(cin, cout, k, 1, s, d)
        y = m(torch.randn(2, cin, 9, 11))
        assert y.shape == (2, cout, 9, 11)
        assert count_params(m) == ghost.ghost_param_count(cin, cout, k, s, d)
    # stride-2 ghost conv halves the size (ceil), as the ResNet stride-2 convs it replaces
    assert ghost.GhostModule(4, 8, 3, 2)(torch.randn(1, 4, 15, 20)).shape == (1, 8, 8, 10)
    # ~1/s of the ordinary convolution's weights (GhostNet Eq. 4)
    assert abs(ghost.ghost_param_count(256, 256, 3, 2, 3, bn=False) / (256 * 256 * 9) - 0.5) < 0.01


def _tied(shape, seed=0):
    g = torch.Generator().manual_seed(seed)
    x = torch.randint(0, 3, shape, generator=g).float()  # many ties inside 2x2 windows
    x[..., :2, :2] = 0.0  # an all-zero window
    return x


@pytest.mark.parametrize("h,w", [(8, 10), (7, 9)])
def test_unpool_first_mode_equals_max_unpool_with_indices_including_ties(h, w):
    for x in (torch.randn(2, 3, h, w), _tied((2, 3, h, w))):
        p, idx = unpool.pool_indices(x)
        y = torch.randn_like(p)
        ref = unpool.unpool_indices(y, idx, (h, w))
        masks, size = unpool.argmax_masks(x)
        assert torch.equal(unpool.unpool_masks(y, masks, size), ref)
        # round trip: unpool(pool(x)) puts every max back at its argmax, zeros elsewhere
        rt = unpool.unpool_masks(p, masks, size)
        assert torch.equal(rt, unpool.unpool_indices(p, idx, (h, w)))
        assert torch.equal(rt.flatten(2).gather(2, idx.flatten(2)), p.flatten(2))  # maxima at argmax
        hit = torch.zeros_like(rt).flatten(2).scatter_(2, idx.flatten(2), 1.0).view_as(rt)
        assert torch.all(rt[hit == 0] == 0)  # zeros elsewhere


@pytest.mark.parametrize("h,w", [(8, 10), (7, 9)])
def test_unpool_mask_mode_equals_indices_without_ties_superset_with_ties(h, w):
    x = torch.randn(2, 3, h, w)  # continuous: a unique max per window
    p, idx = unpool.pool_indices(x)
    y = torch.randn_like(p)
    assert torch.equal(unpool.unpool_mask(y, unpool.max_mask(x)), unpool.unpool_indices(y, idx, (h, w)))
    xt = _tied((2, 3, h, w), 1)
    p, idx = unpool.pool_indices(xt)
    y = torch.rand_like(p) + 1.0
    got = unpool.unpool_mask(y, unpool.max_mask(xt))
    ref = unpool.unpool_indices(y, idx, (h, w))
    assert torch.equal(got.flatten(2).gather(2, idx.flatten(2)), y.flatten(2))  # the argmax is always hit
    assert torch.equal(got[ref != 0], ref[ref != 0])
    assert torch.equal((got != 0) & (xt != F.interpolate(p, scale_factor=2.0)[..., :h, :w]),
                       torch.zeros_like(got, dtype=torch.bool))  # only at (tied) maxima


def test_stride1_deconv_equals_conv_transpose():
    d = Deconv(6, 4, 3, 1, 1, bias=True)
    x = torch.randn(1, 6, 7, 9)
    ref = F.conv_transpose2d(x, d.weight, d.bias, 1, 1)
    assert torch.allclose(d(x), ref, atol=1e-5)
    assert torch.allclose(d.as_conv()(x), ref, atol=1e-5)


@pytest.mark.parametrize("config", ["fnet-lite", "fnet"])
def test_encoder_decoder_output_shapes(config):
    m = build_model(config).eval()
    x = torch.rand(1, 3, 64, 96)
    with torch.no_grad():
        feats = m.encoder((x - m.mean) / m.std)
        assert [tuple(f.shape[1:]) for f in feats] == [
            (c, 64 // 2 ** (i + 1), 96 // 2 ** (i + 1)) for i, c in enumerate(m.encoder.channels)]
        # fnet-lite leaves the last x2 to its consumer (final_up "none"): logits at H/2
        f = 2 if m.cfg.final_up == "none" else 1
        assert m.decoder(feats).shape == (1, 21, 64 // f, 96 // f)
        assert m(torch.rand(1, 3, 48, 80)).shape == (1, 21, 48 // f, 80 // f)  # 48/32 not whole: odd sizes
        assert upsample_logits(m(x), (64, 96)).shape == (1, 21, 64, 96)


def test_resnet50_layout():
    m = build_model("fnet")
    assert [len(s) for s in m.encoder.stages] == [3, 4, 6, 3]
    assert m.encoder.channels == [64, 256, 512, 1024, 2048]
    convs = [mod for mod in m.encoder.modules() if isinstance(mod, torch.nn.Conv2d)]
    ghosts = [mod for mod in m.encoder.modules() if isinstance(mod, ghost.GhostModule)]
    assert len(convs) == 2 * len(ghosts) == 2 * (1 + 16 * 3 + 4)  # every conv is inside a Ghost module


def test_param_count_s2_within_10_percent_of_paper():
    n = count_params(build_model("fnet", s=2))
    assert abs(n - 12.2e6) / 12.2e6 < 0.10, n
    assert count_params(build_model("fnet", s=3)) < n  # larger s, fewer parameters (Table 3 trend)


def test_few_adam_steps_lower_the_loss():
    torch.manual_seed(0)
    m = build_model("fnet-lite").train()
    x = torch.rand(2, 3, 64, 64)
    y = torch.randint(0, 21, (2, 64, 64))
    y[:, :4] = 255
    opt = torch.optim.Adam(m.parameters(), lr=1e-2)
    loss_fn = torch.nn.CrossEntropyLoss(ignore_index=255)
    losses = []
    for _ in range(6):
        loss = loss_fn(upsample_logits(m(x), y.shape[-2:]), y)
        opt.zero_grad()
        loss.backward()
        opt.step()
        losses.append(float(loss))
    assert losses[-1] < losses[0]


def test_encoder_freezing():
    m = build_model("fnet-lite")
    m.set_encoder_frozen(True)
    m.train()
    assert not m.encoder.training and m.decoder.training
    assert all(not p.requires_grad for p in m.encoder.parameters())
    m.set_encoder_frozen(False)
    m.train()
    assert m.encoder.training and all(p.requires_grad for p in m.encoder.parameters())


def _write_voc(root, n=5, val=True, size=(40, 30)):
    cv2 = pytest.importorskip("cv2")
    pytest.importorskip("PIL", reason="python3-pil not installed")
    from training.fnet.voc import write_label_png
    for d in ("JPEGImages", "SegmentationClass", "ImageSets/Segmentation"):
        os.makedirs(os.path.join(root, d), exist_ok=True)
    rng = np.random.default_rng(0)
    ids = [f"2007_{i:06d}" for i in range(n)]
    for i, name in enumerate(ids):
        w, h = size
        cv2.imwrite(os.path.join(root, "JPEGImages", name + ".jpg"), rng.integers(0, 255, (h, w, 3), dtype=np.uint8))
        lab = np.zeros((h, w), np.uint8)
        lab[5:15, 5:20] = 1 + i % 20
        lab[4, :] = 255  # boundary / ignore
        write_label_png(os.path.join(root, "SegmentationClass", name + ".png"), lab)
    sets = os.path.join(root, "ImageSets", "Segmentation")
    with open(os.path.join(sets, "train.txt"), "w") as f:
        f.write("\n".join(ids[:4] if val else ids) + "\n")
    if val:
        with open(os.path.join(sets, "val.txt"), "w") as f:
            f.write(ids[4] + "\n")
    return ids


def test_voc_reader_palette_indices_split_and_augmentation(tmp_path):
    from training.fnet.voc import Augment, VOCSegmentation, read_label, split_ids
    root = str(tmp_path / "voc")
    ids = _write_voc(root, n=10, val=False)
    lab = read_label(os.path.join(root, "SegmentationClass", ids[3] + ".png"))
    assert lab.dtype == np.uint8 and set(np.unique(lab)) == {0, 4, 255}  # indices, not colours
    tr, va = split_ids(root, 0.1, seed=0)
    assert len(va) == 1 and len(tr) == 9 and not set(tr) & set(va) and split_ids(root, 0.1, 0) == (tr, va)
    ds = VOCSegmentation(root, tr, (32, 32), Augment((32, 32)), seed=3)
    x, y = ds[0]
    assert x.shape == (3, 32, 32) and x.dtype == np.float32 and 0 <= x.min() and x.max() <= 1
    assert y.shape == (32, 32) and set(np.unique(y)) <= {0, 255} | set(range(1, 21))
    x2, y2 = ds[0]
    assert np.array_equal(x, x2) and np.array_equal(y, y2)  # seeded per (seed, epoch, index)
    ds.epoch = 1
    assert not np.array_equal(ds[0][0], x)


def test_train_cli_resume_and_evaluate(tmp_path, capsys):
    from training.fnet import evaluate, train
    root = str(tmp_path / "voc")
    _write_voc(root)
    out = str(tmp_path / "run")
    common = ["--voc", root, "--out", out, "--config", "fnet-lite", "--batch", "2", "--input-size", "32x32",
              "--freeze-epochs", "1", "--max-steps", "1"]
    assert train.main(common + ["--epochs", "1"]) == 0
    assert train.main(common + ["--epochs", "2", "--resume", os.path.join(out, "last.pt")]) == 0
    for f in ("last.pt", "best.pt", "epoch_002.pt", "history.csv", "loss.png"):
        assert os.path.exists(os.path.join(out, f)), f
    ck = torch.load(os.path.join(out, "last.pt"))
    assert ck["epoch"] == 2 and [h["frozen"] for h in ck["history"]] == [True, False]
    assert evaluate.main(["--voc", root, "--ckpt", os.path.join(out, "best.pt"), "--input-size", "32x32",
                          "--threads", "1"]) == 0
    text = capsys.readouterr().out
    assert "| aeroplane |" in text and "MPA / mIoU" in text and "ms/frame" in text


def test_train_cli_init_fine_tunes_from_a_whole_model(tmp_path):
    from training.fnet import train
    root = str(tmp_path / "voc")
    _write_voc(root)
    common = ["--voc", root, "--config", "fnet-lite", "--batch", "2", "--freeze-epochs", "0", "--max-steps", "1",
              "--epochs", "1", "--lr", "0"]  # lr 0: the weights must come through unchanged
    first = str(tmp_path / "first")
    assert train.main(common + ["--out", first, "--input-size", "32x32"]) == 0
    second = str(tmp_path / "second")  # another input size, as for the shipped model
    assert train.main(common + ["--out", second, "--input-size", "48x32", "--init",
                                os.path.join(first, "last.pt")]) == 0
    a, b = torch.load(os.path.join(first, "last.pt")), torch.load(os.path.join(second, "last.pt"))
    assert b["epoch"] == 1 and len(b["history"]) == 1  # a fresh run, not a resume
    for k, v in a["model"].items():
        if "running" not in k and "num_batches" not in k:  # BN statistics still move in train mode
            assert torch.equal(v, b["model"][k]), k
    # Another configuration: what fits is taken, the rest starts fresh; nothing fitting is an error.
    from training.fnet.train import init_from
    other = build_model("fnet-lite", lateral="ghost")
    path = str(tmp_path / "other.pt")
    torch.save({"model": other.state_dict(), "config": other.cfg.to_dict()}, path)
    target = build_model("fnet-lite")
    init_from(target, path)
    got = target.state_dict()
    assert torch.equal(got["encoder.stem.primary.0.weight"], other.state_dict()["encoder.stem.primary.0.weight"])
    assert "decoder.lateral.0.0.weight" in got and "decoder.lateral.0.0.weight" not in other.state_dict()
    torch.save({"model": {"unrelated": torch.zeros(3)}}, path)
    with pytest.raises(SystemExit, match="no tensor that fits"):
        init_from(build_model("fnet-lite"), path)


@pytest.mark.parametrize("mode", ["mask", "first"])
def test_export_onnx_matches_torch_in_opencv_dnn(tmp_path, mode):
    cv2 = pytest.importorskip("cv2")
    from training.fnet.export import export_onnx
    torch.manual_seed(0)
    m = build_model("fnet-lite", unpool=mode).eval()
    with torch.no_grad():  # non-trivial BN statistics so the folded graph is really exercised
        for mod in m.modules():
            if isinstance(mod, torch.nn.BatchNorm2d):
                mod.running_mean.uniform_(-0.2, 0.2)
                mod.running_var.uniform_(0.5, 1.5)
    path = str(tmp_path / "lite.onnx")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        card = export_onnx(m, path, (64, 48), verify=True)
    assert card["opencv"]["max_abs_diff_vs_torch"] < 1e-4
    net = cv2.dnn.readNetFromONNX(path)
    rgb = np.random.default_rng(1).random((48, 64, 3)).astype(np.float32)
    net.setInput(cv2.dnn.blobFromImage(rgb, 1.0, (64, 48), swapRB=False, crop=False))
    got = net.forward()
    with torch.no_grad():
        ref = m(torch.from_numpy(rgb.transpose(2, 0, 1)[None].copy())).numpy()
    assert got.shape == (1, 21, 24, 32)  # fnet-lite: logits at H/2
    assert np.abs(got - ref).max() < 1e-4
    assert os.path.exists(str(tmp_path / "lite.json"))
