"""The boll network: a small one-stage detector (tiny-YOLO-like) with two heads.

Input: RGB image 448x256 (1280x720 frames resized), values in [0, 1]. Output: two maps of raw scores,
stride 8 (56x32 cells) and stride 16 (28x16 cells), each with ANCHORS_PER_HEAD anchors x (5 + classes) channels:
tx, ty, tw, th, objectness, class scores. Decoding (the same in C++, network_boll_detector.cpp):
  cx = (col + sigmoid(tx)) * stride, cy = (row + sigmoid(ty)) * stride,
  w = anchor_w * exp(tw), h = anchor_h * exp(th), score = sigmoid(obj) * sigmoid(class).
Layers are the ones OpenCV 4.6's ONNX importer runs: Conv (BatchNorm folded at export), LeakyReLU, Upsample
(nearest), Concat.
"""
import torch
import torch.nn as nn

INPUT_W, INPUT_H = 448, 256
CLASSES = ["boll", "end_effector"]
STRIDES = [8, 16]
# Anchors [px at the network input], per head: bolls are 12-27 px across, the end-effector 25-80 px.
ANCHORS = [[(14.0, 14.0), (24.0, 24.0)], [(36.0, 36.0), (64.0, 64.0)]]
ANCHORS_PER_HEAD = 2


def conv(cin, cout, k=3, s=1):
    return nn.Sequential(nn.Conv2d(cin, cout, k, s, k // 2, bias=False), nn.BatchNorm2d(cout),
                         nn.LeakyReLU(0.1, inplace=True))


class BollNet(nn.Module):
    def __init__(self, classes=len(CLASSES), width=1.0):
        super().__init__()
        c = [int(round(x * width)) for x in (16, 32, 64, 128)]
        out = ANCHORS_PER_HEAD * (5 + classes)
        self.stem = nn.Sequential(conv(3, c[0], 3, 2), conv(c[0], c[1], 3, 2), conv(c[1], c[1]))
        self.s8 = nn.Sequential(conv(c[1], c[2], 3, 2), conv(c[2], c[2]))
        self.s16 = nn.Sequential(conv(c[2], c[3], 3, 2), conv(c[3], c[3]))
        self.head16 = nn.Conv2d(c[3], out, 1)
        self.reduce = conv(c[3], c[2], 1)
        self.up = nn.Upsample(scale_factor=2, mode="nearest")
        self.fuse = conv(2 * c[2], c[2])
        self.head8 = nn.Conv2d(c[2], out, 1)
        for head in (self.head8, self.head16):  # objectness starts near 1 %: the loss is not swamped at first
            with torch.no_grad():
                head.bias.view(ANCHORS_PER_HEAD, -1)[:, 4].fill_(-4.6)

    def forward(self, x):
        f8 = self.s8(self.stem(x))
        f16 = self.s16(f8)
        p16 = self.head16(f16)
        p8 = self.head8(self.fuse(torch.cat([self.up(self.reduce(f16)), f8], 1)))
        return p8, p16


def decode(outputs, classes=len(CLASSES)):
    """Raw maps -> list of (N, A*H*W, 5+classes) tensors [cx, cy, w, h (input px), obj, obj*class...]."""
    decoded = []
    for p, stride, anchors in zip(outputs, STRIDES, ANCHORS):
        n, _, h, w = p.shape
        p = p.view(n, ANCHORS_PER_HEAD, 5 + classes, h, w).permute(0, 1, 3, 4, 2)
        gy, gx = torch.meshgrid(torch.arange(h), torch.arange(w), indexing="ij")
        a = torch.tensor(anchors, dtype=p.dtype).view(1, ANCHORS_PER_HEAD, 1, 1, 2)
        cx = (gx + torch.sigmoid(p[..., 0])) * stride
        cy = (gy + torch.sigmoid(p[..., 1])) * stride
        wh = a * torch.exp(p[..., 2:4].clamp(max=6.0))
        obj = torch.sigmoid(p[..., 4:5])
        cls = torch.sigmoid(p[..., 5:]) * obj
        decoded.append(torch.cat([cx[..., None], cy[..., None], wh, obj, cls], -1).reshape(n, -1, 5 + classes))
    return decoded
