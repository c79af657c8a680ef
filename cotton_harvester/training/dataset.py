"""Labelled frames from boll_dataset_export (images/*.png, labels/*.txt in YOLO format) with augmentation.

Augmentation (training only): scale 0.75-1.3 with a random interpolation, a random crop to the training size
(padded grey where the scaled frame is smaller), horizontal and vertical flips (the camera looks straight down),
HSV jitter (hue +-6 of 180, saturation and value x0.6-1.4), Gaussian blur (30 %) and pixel noise (30 %).
"""
import glob
import os
import random

import cv2
import numpy as np

from boll_net import INPUT_W, INPUT_H


def read_labels(path):
    """[(class, cx, cy, w, h)] normalised to the image; empty when the file is missing."""
    if not os.path.exists(path):
        return np.zeros((0, 5), np.float32)
    rows = [list(map(float, line.split())) for line in open(path) if line.strip()]
    return np.array(rows, np.float32).reshape(-1, 5)


def seed_of(name):
    """The simulation seed of a frame named s<seed>_<k>."""
    return int(os.path.basename(name)[1:].split("_")[0])


class Frames:
    """The frames of one or more export folders; `seeds` (a range) keeps only those seeds."""

    def __init__(self, roots, seeds=None):
        self.roots, self.seeds = roots, seeds
        self.rescan()

    def rescan(self):
        self.items = []
        for root in self.roots:
            for image in sorted(glob.glob(os.path.join(root, "images", "*.png"))):
                name = os.path.splitext(os.path.basename(image))[0]
                label = os.path.join(root, "labels", name + ".txt")
                if not os.path.exists(label):
                    continue  # still being written
                if self.seeds is not None and seed_of(name) not in self.seeds:
                    continue
                self.items.append((image, label))
        return len(self.items)

    def load(self, index):
        """RGB image at the network input size and labels in pixels [(class, x0, y0, x1, y1)]."""
        image_path, label_path = self.items[index]
        bgr = cv2.imread(image_path, cv2.IMREAD_COLOR)
        if bgr.shape[1] != INPUT_W or bgr.shape[0] != INPUT_H:
            bgr = cv2.resize(bgr, (INPUT_W, INPUT_H), interpolation=cv2.INTER_AREA)
        rgb = cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)
        lab = read_labels(label_path)
        boxes = np.zeros((len(lab), 5), np.float32)
        if len(lab):
            boxes[:, 0] = lab[:, 0]
            boxes[:, 1] = (lab[:, 1] - lab[:, 3] / 2) * INPUT_W
            boxes[:, 2] = (lab[:, 2] - lab[:, 4] / 2) * INPUT_H
            boxes[:, 3] = (lab[:, 1] + lab[:, 3] / 2) * INPUT_W
            boxes[:, 4] = (lab[:, 2] + lab[:, 4] / 2) * INPUT_H
        return rgb, boxes


def augment(rgb, boxes, crop_w, crop_h, rng):
    """The training augmentation; returns an image of crop_w x crop_h and its boxes (class, x0, y0, x1, y1)."""
    s = rng.uniform(0.75, 1.3)
    interp = rng.choice([cv2.INTER_AREA, cv2.INTER_LINEAR, cv2.INTER_NEAREST])
    img = cv2.resize(rgb, None, fx=s, fy=s, interpolation=interp)
    b = boxes.copy()
    b[:, 1:] *= s
    out = np.full((crop_h, crop_w, 3), 127, np.uint8)
    ox = rng.randint(min(0, img.shape[1] - crop_w), max(0, img.shape[1] - crop_w))
    oy = rng.randint(min(0, img.shape[0] - crop_h), max(0, img.shape[0] - crop_h))
    sx0, sy0 = max(ox, 0), max(oy, 0)
    sx1, sy1 = min(ox + crop_w, img.shape[1]), min(oy + crop_h, img.shape[0])
    out[sy0 - oy:sy1 - oy, sx0 - ox:sx1 - ox] = img[sy0:sy1, sx0:sx1]
    b[:, [1, 3]] -= ox
    b[:, [2, 4]] -= oy
    if rng.random() < 0.5:
        out = out[:, ::-1]
        b[:, [1, 3]] = crop_w - b[:, [3, 1]]
    if rng.random() < 0.5:
        out = out[::-1]
        b[:, [2, 4]] = crop_h - b[:, [4, 2]]
    out = np.ascontiguousarray(out)
    hsv = cv2.cvtColor(out, cv2.COLOR_RGB2HSV).astype(np.float32)
    hsv[..., 0] = (hsv[..., 0] + rng.uniform(-6, 6)) % 180
    hsv[..., 1] *= rng.uniform(0.6, 1.4)
    hsv[..., 2] *= rng.uniform(0.6, 1.4)
    out = cv2.cvtColor(np.clip(hsv, 0, 255).astype(np.uint8), cv2.COLOR_HSV2RGB)
    if rng.random() < 0.3:
        out = cv2.GaussianBlur(out, (0, 0), rng.uniform(0.5, 1.2))
    if rng.random() < 0.3:
        out = np.clip(out + np.random.normal(0, rng.uniform(2, 8), out.shape), 0, 255).astype(np.uint8)
    # Keep boxes with at least 60 % of their area inside the crop, clipped to it.
    full = (b[:, 3] - b[:, 1]) * (b[:, 4] - b[:, 2])
    b[:, [1, 3]] = b[:, [1, 3]].clip(0, crop_w)
    b[:, [2, 4]] = b[:, [2, 4]].clip(0, crop_h)
    kept = (b[:, 3] - b[:, 1]) * (b[:, 4] - b[:, 2]) >= 0.6 * np.maximum(full, 1e-6)
    return out, b[kept]
