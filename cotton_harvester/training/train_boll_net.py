#!/usr/bin/python3
"""Trains the boll network (boll_net.py) on frames from boll_dataset_export, time-boxed, on the CPU.

  OMP_NUM_THREADS=1 nice -n 19 /usr/bin/python3 train_boll_net.py --data DIR [--data DIR2] --minutes 110 \
      --out boll_net.pt [--seeds 1000:9000] [--threads 1]

The learning rate follows a cosine over the time budget (Adam, 2e-3 down to 1e-4), so a run of any length ends
annealed. The folders are rescanned every epoch: frames still being exported join the training as they appear.
A checkpoint is written every --save-every steps and at the end.
"""
import argparse
import math
import random
import sys
import time

import numpy as np
import torch
import torch.nn.functional as F

from boll_net import ANCHORS, ANCHORS_PER_HEAD, CLASSES, STRIDES, BollNet
from dataset import Frames, augment


def build_targets(boxes_list, shapes):
    """Per head: (obj, txy, twh, cls, mask) targets. Each box goes to the anchor of best shape (of all heads) in the
    cell holding its centre."""
    n = len(boxes_list)
    all_anchors = [(h, a, wh) for h, anchors in enumerate(ANCHORS) for a, wh in enumerate(anchors)]
    targets = []
    for (gh, gw) in shapes:
        targets.append({
            "obj": torch.zeros(n, ANCHORS_PER_HEAD, gh, gw),
            "txy": torch.zeros(n, ANCHORS_PER_HEAD, gh, gw, 2),
            "twh": torch.zeros(n, ANCHORS_PER_HEAD, gh, gw, 2),
            "cls": torch.zeros(n, ANCHORS_PER_HEAD, gh, gw, len(CLASSES)),
        })
    for i, boxes in enumerate(boxes_list):
        for c, x0, y0, x1, y1 in boxes:
            w, h = x1 - x0, y1 - y0
            if w < 2 or h < 2:
                continue
            cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
            ious = [min(w, aw) * min(h, ah) / (w * h + aw * ah - min(w, aw) * min(h, ah)) for _, _, (aw, ah) in all_anchors]
            head, a, (aw, ah) = all_anchors[int(np.argmax(ious))]
            stride = STRIDES[head]
            gh, gw = shapes[head]
            gx, gy = min(int(cx / stride), gw - 1), min(int(cy / stride), gh - 1)
            t = targets[head]
            t["obj"][i, a, gy, gx] = 1.0
            t["txy"][i, a, gy, gx] = torch.tensor([cx / stride - gx, cy / stride - gy])
            t["twh"][i, a, gy, gx] = torch.tensor([math.log(w / aw), math.log(h / ah)])
            t["cls"][i, a, gy, gx, int(c)] = 1.0
    return targets


def loss_of(outputs, targets):
    total, parts = 0.0, np.zeros(3)
    n = outputs[0].shape[0]
    for p, t in zip(outputs, targets):
        _, _, gh, gw = p.shape
        p = p.view(n, ANCHORS_PER_HEAD, 5 + len(CLASSES), gh, gw).permute(0, 1, 3, 4, 2)
        pos = t["obj"] > 0.5
        obj = F.binary_cross_entropy_with_logits(p[..., 4], t["obj"], reduction="sum")
        box = torch.zeros(())
        cls = torch.zeros(())
        if pos.any():
            box = F.binary_cross_entropy_with_logits(p[..., 0:2][pos], t["txy"][pos], reduction="sum") + \
                F.smooth_l1_loss(p[..., 2:4][pos], t["twh"][pos], reduction="sum", beta=0.2) * 2.0
            cls = F.binary_cross_entropy_with_logits(p[..., 5:][pos], t["cls"][pos], reduction="sum")
        total = total + (obj + 2.0 * box + cls) / n
        parts += np.array([obj.item(), box.item(), cls.item()]) / n
    return total, parts


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", action="append", required=True)
    ap.add_argument("--seeds", default="1000:9000", help="first:end seeds used for training (held-out: 9000 on)")
    ap.add_argument("--minutes", type=float, default=110.0)
    ap.add_argument("--batch", type=int, default=12)
    ap.add_argument("--crop", default="320x256", help="training crop WxH (multiples of 16)")
    ap.add_argument("--lr", type=float, default=2e-3)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default="boll_net.pt")
    ap.add_argument("--resume", default="")
    ap.add_argument("--save-every", type=int, default=100)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    rng = random.Random(args.seed)
    np.random.seed(args.seed)
    lo, hi = map(int, args.seeds.split(":"))
    frames = Frames(args.data, range(lo, hi))
    crop_w, crop_h = map(int, args.crop.split("x"))
    shapes = [(crop_h // s, crop_w // s) for s in STRIDES]
    model = BollNet()
    if args.resume:
        model.load_state_dict(torch.load(args.resume)["model"])
    opt = torch.optim.Adam(model.parameters(), lr=args.lr, weight_decay=1e-5)
    start, step, epoch = time.time(), 0, 0
    budget = args.minutes * 60.0
    running = None
    while time.time() - start < budget:
        count = frames.rescan()
        order = list(range(count))
        rng.shuffle(order)
        epoch += 1
        print(f"epoch {epoch}: {count} frames", flush=True)
        for b0 in range(0, len(order) - args.batch + 1, args.batch):
            elapsed = time.time() - start
            if elapsed >= budget:
                break
            lr = 1e-4 + 0.5 * (args.lr - 1e-4) * (1 + math.cos(math.pi * elapsed / budget))
            if step < 50:
                lr *= (step + 1) / 50.0  # warm-up
            for g in opt.param_groups:
                g["lr"] = lr
            images, boxes = [], []
            for i in order[b0:b0 + args.batch]:
                img, bx = augment(*frames.load(i), crop_w, crop_h, rng)
                images.append(img)
                boxes.append(bx)
            x = torch.from_numpy(np.stack(images)).permute(0, 3, 1, 2).float() / 255.0
            model.train()
            loss, parts = loss_of(model(x), build_targets(boxes, shapes))
            opt.zero_grad()
            loss.backward()
            torch.nn.utils.clip_grad_norm_(model.parameters(), 10.0)
            opt.step()
            step += 1
            running = parts if running is None else 0.95 * running + 0.05 * parts
            if step % 20 == 0:
                print(f"step {step} {elapsed / 60:.1f} min lr {lr:.5f} obj {running[0]:.3f} box {running[1]:.3f} "
                      f"cls {running[2]:.3f}", flush=True)
            if step % args.save_every == 0:
                torch.save({"model": model.state_dict(), "step": step, "epoch": epoch}, args.out)
    torch.save({"model": model.state_dict(), "step": step, "epoch": epoch,
                "minutes": (time.time() - start) / 60.0, "frames": frames.rescan()}, args.out)
    print(f"done: {step} steps, {epoch} epochs, {(time.time() - start) / 60:.1f} min -> {args.out}")


if __name__ == "__main__":
    sys.exit(main())
