"""Stacks pictures (rows of a sheet) top to bottom into one JPEG.

Usage: stack_rows.py OUT.jpg ROW.png [ROW.png ...]   (needs pillow)"""
import sys
from PIL import Image

out, rows = sys.argv[1], [Image.open(p).convert("RGB") for p in sys.argv[2:]]
sheet = Image.new("RGB", (max(r.width for r in rows), sum(r.height for r in rows)), "white")
y = 0
for r in rows:
    sheet.paste(r, (0, y))
    y += r.height
sheet.save(out, quality=80)
