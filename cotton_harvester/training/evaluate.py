#!/usr/bin/python3
"""Recall and precision of a boll network checkpoint on labelled frames (IoU >= 0.4 with a label), per class.

  /usr/bin/python3 evaluate.py --checkpoint boll_net.pt --data DIR [--seeds 9000:9100] [--threshold 0.4]
"""
import argparse

import cv2
import numpy as np
import torch

from boll_net import CLASSES, INPUT_H, INPUT_W, BollNet, decode
from dataset import Frames


def iou(a, b):
    x0, y0 = max(a[0], b[0]), max(a[1], b[1])
    x1, y1 = min(a[2], b[2]), min(a[3], b[3])
    inter = max(0.0, x1 - x0) * max(0.0, y1 - y0)
    return inter / ((a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter + 1e-9)


def nms(boxes, scores, threshold):
    order, kept = np.argsort(-scores), []
    for i in order:
        if all(iou(boxes[i], boxes[k]) <= threshold for k in kept):
            kept.append(i)
    return kept


def detections(model, rgb, cls, threshold, nms_threshold=0.4):
    x = torch.from_numpy(rgb).permute(2, 0, 1)[None].float() / 255.0
    with torch.no_grad():
        rows = torch.cat(decode(model(x)), 1)[0].numpy()
    rows = rows[rows[:, 5 + cls] >= threshold]
    boxes = np.stack([rows[:, 0] - rows[:, 2] / 2, rows[:, 1] - rows[:, 3] / 2,
                      rows[:, 0] + rows[:, 2] / 2, rows[:, 1] + rows[:, 3] / 2], 1) if len(rows) else np.zeros((0, 4))
    return boxes[nms(boxes, rows[:, 5 + cls], nms_threshold)] if len(rows) else boxes


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--checkpoint", required=True)
    ap.add_argument("--data", action="append", required=True)
    ap.add_argument("--seeds", default="9000:100000")
    ap.add_argument("--threshold", type=float, default=0.4)
    args = ap.parse_args()
    torch.set_num_threads(1)
    model = BollNet()
    model.load_state_dict(torch.load(args.checkpoint)["model"])
    model.eval()
    lo, hi = map(int, args.seeds.split(":"))
    frames = Frames(args.data, range(lo, hi))
    for cls, name in enumerate(CLASSES):
        tp = fp = fn = 0
        for i in range(len(frames.items)):
            rgb, boxes = frames.load(i)
            truth = [b[1:] for b in boxes if int(b[0]) == cls]
            found = detections(model, rgb, cls, args.threshold)
            matched = [any(iou(t, d) >= 0.4 for d in found) for t in truth]
            tp += sum(matched)
            fn += len(truth) - sum(matched)
            fp += sum(not any(iou(t, d) >= 0.4 for t in truth) for d in found)
        print(f"{name}: frames {len(frames.items)} labels {tp + fn} found {tp} false {fp} "
              f"recall {tp / max(tp + fn, 1):.3f} precision {tp / max(tp + fp, 1):.3f}")


if __name__ == "__main__":
    main()
