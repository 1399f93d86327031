"""Draws scenes/blocks/seesaw.png and pendulum.png (one pixel per block; blue is pinned).
Run from the project root: python3 scenes/blocks/draw_joint_scenes.py"""
import zlib, struct, json, sys
def png(path, w, h, pix):
    raw=b''.join(b'\x00'+b''.join(bytes(pix.get((x,y),(255,255,255))) for x in range(w)) for y in range(h))
    def chunk(t,d): return struct.pack('>I',len(d))+t+d+struct.pack('>I',zlib.crc32(t+d)&0xffffffff)
    open(path,'wb').write(b'\x89PNG\r\n\x1a\n'+chunk(b'IHDR',struct.pack('>IIBBBBB',w,h,8,2,0,0,0))+chunk(b'IDAT',zlib.compress(raw,9))+chunk(b'IEND',b''))
BLUE=(0,0,163); DARK=(40,40,40); RED=(200,30,30); GREEN=(30,140,30)
# seesaw: ground row 13, fulcrum triangle rows 10-12, plank row 8 cols 4..16, loads row 5 at cols 5 and 15
pix={}
for x in range(21): pix[(x,13)]=BLUE
for r,half in ((10,0),(11,1),(12,2)):
    for x in range(10-half,11+half): pix[(x,r)]=BLUE
for x in range(4,17): pix[(x,8)]=DARK
pix[(5,5)]=RED; pix[(15,5)]=RED
png('scenes/blocks/seesaw.png',21,14,pix)
# pendulum: support block (2,2) blue, plank row 2 cols 5..11; spring: support (18,1) blue, bob 2x2 at (17..18, 6..7)
pix={}
pix[(2,2)]=BLUE
for x in range(5,12): pix[(x,2)]=DARK
pix[(18,1)]=BLUE
for x in (17,18):
    for y in (6,7): pix[(x,y)]=GREEN
png('scenes/blocks/pendulum.png',22,16,pix)
