#!/usr/bin/env python3
"""Groom a head of hair with ringlet, cut it, and export it as .hair and .usda.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/groom_cut_export.py \
        examples/hairstyles/wavy.json out/python --cut-z -0.12

Grooms the hairstyle (masters solved with body contact, wisps grown), cuts every master below
the height z (metres; the hair re-settles and the tips rise: --settle re-cuts until they lie on
the plane), and writes OUTDIR/cut.hair and OUTDIR/cut.usda (metres, z up).
"""
import argparse
import os

import numpy as np

import ringlet


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("hairstyle", help="hairstyle file (docs/hairstyle-format.md)")
    parser.add_argument("outdir", help="directory to write cut.hair and cut.usda into")
    parser.add_argument("--cut-z", type=float, default=-0.12, help="cut height (m)")
    parser.add_argument("--settle", action="store_true", help="re-cut until the tips settle")
    args = parser.parse_args()

    groom = ringlet.groom(args.hairstyle)
    s = groom.summary
    print("groomed %d masters (%d converged, %d unstable), %d strands, %d points in %.2f s" % (
        s.masters, s.converged, s.unstable, s.strands, s.points,
        s.solve_seconds + s.wisp_seconds))
    lowest = groom.strands.points[:, 2].min()

    styled = ringlet.StyledHair(groom)
    report = styled.cut(z=args.cut_z, settle=args.settle)
    print("cut: %s" % report.message)
    strands = styled.strands()
    counts = strands.point_counts                     # (N,) uint32, a view
    lengths = [np.linalg.norm(np.diff(strands.points[a:b], axis=0), axis=1).sum()
               for a, b in zip(strands.offsets()[:-1], strands.offsets()[1:])]
    print("%d strands, %d points; lowest point %.4f m before, %.4f m after; mean strand length "
          "%.4f m" % (len(counts), counts.sum(), lowest, strands.points[:, 2].min(),
                      np.mean(lengths)))

    os.makedirs(args.outdir, exist_ok=True)
    ringlet.write_hair_file(os.path.join(args.outdir, "cut.hair"), strands, overwrite=True)
    ringlet.write_usda(os.path.join(args.outdir, "cut.usda"), strands, overwrite=True)
    print("wrote %s/cut.hair and %s/cut.usda" % (args.outdir, args.outdir))


if __name__ == "__main__":
    main()
