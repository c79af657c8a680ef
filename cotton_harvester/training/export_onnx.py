#!/usr/bin/python3
"""Exports a trained boll network (train_boll_net.py checkpoint) to ONNX for OpenCV DNN and checks that OpenCV's
outputs match torch's on a frame.

  /usr/bin/python3 export_onnx.py --checkpoint boll_net.pt --out ../models/boll_net.onnx [--image frame.png]
  /usr/bin/python3 export_onnx.py --random --out random.onnx    (untrained weights, for tests)

Inputs: 1x3x256x448 RGB in [0, 1]; outputs `p8` (1x14x32x56) and `p16` (1x14x16x28), raw (see boll_net.py).
BatchNorm is folded into the convolutions by the export (eval mode).
"""
import argparse

import cv2
import numpy as np
import onnx
import torch

from boll_net import INPUT_H, INPUT_W, BollNet


def inline_identities(path):
    """The exporter shares equal folded constants through Identity nodes, which OpenCV 4.6 cannot read: give each
    output its own copy of the constant."""
    model = onnx.load(path)
    inits = {i.name: i for i in model.graph.initializer}
    for node in [n for n in model.graph.node if n.op_type == "Identity" and n.input[0] in inits]:
        copy = onnx.TensorProto()
        copy.CopyFrom(inits[node.input[0]])
        copy.name = node.output[0]
        model.graph.initializer.append(copy)
        model.graph.node.remove(node)
    onnx.checker.check_model(model)
    onnx.save(model, path)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--checkpoint", default="")
    ap.add_argument("--random", action="store_true")
    ap.add_argument("--out", required=True)
    ap.add_argument("--image", default="")
    args = ap.parse_args()
    torch.set_num_threads(1)
    model = BollNet()
    if not args.random:
        model.load_state_dict(torch.load(args.checkpoint)["model"])
    model.eval()
    dummy = torch.zeros(1, 3, INPUT_H, INPUT_W)
    torch.onnx.export(model, dummy, args.out, opset_version=11, input_names=["image"], output_names=["p8", "p16"],
                      do_constant_folding=True)
    inline_identities(args.out)
    if args.image:
        bgr = cv2.resize(cv2.imread(args.image), (INPUT_W, INPUT_H), interpolation=cv2.INTER_AREA)
    else:
        bgr = (np.random.RandomState(0).rand(INPUT_H, INPUT_W, 3) * 255).astype(np.uint8)
    blob = cv2.dnn.blobFromImage(bgr, 1.0 / 255.0, (INPUT_W, INPUT_H), swapRB=True)
    net = cv2.dnn.readNetFromONNX(args.out)
    net.setInput(blob)
    cv_out = net.forward(["p8", "p16"])
    with torch.no_grad():
        torch_out = model(torch.from_numpy(blob))
    for name, a, b in zip(["p8", "p16"], cv_out, torch_out):
        print(f"{name}: shape {a.shape}, max |opencv - torch| {np.abs(a - b.numpy()).max():.2e}")


if __name__ == "__main__":
    main()
