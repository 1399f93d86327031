"""Makes the rattleback's body: scenes/data/rattleback.obj (a tessellated ellipsoid, semi-axes
0.20 x 0.02 x 0.03 m along body x, y (vertical), z, its centre 1 cm above the centre of mass, for
drawing) and scenes/data/rattleback.json (mass 1 kg and the inertia about the centre of mass:
principal moments A = 2e-4 about the long axis x, C = 1.7e-3 about the vertical y, B = 1.6e-3
about z, the principal axes turned by delta = 0.8 degrees about +y: the shape's "slightly
rotated" inertia). The numbers are Kane and Levinson's rattleback (1982) as given in the
Autolev/MotionGenesis rattleback example: semi-diameters 2 cm (vertical), 20 cm, 3 cm, h = 1 cm,
m = 1 kg, central moments 17 (vertical), 2 (long axis), 16 kg cm^2, product of inertia of the two
horizontal axes 0.2 kg cm^2; turning the principal axes by 0.8 degrees gives 0.195 kg cm^2. See
docs/contact.md section "The rattleback".

    python3 scenes/src/rattleback.py          # from the project root
"""
import math, json, sys
a,b,c = 0.20, 0.02, 0.03   # x long, y vertical, z
h = 0.01                    # COM below the ellipsoid centre
m = 1.0
A, B, C = 0.0002, 0.0016, 0.0017  # about x (long), z (short horizontal), y (vertical)
delta = float(sys.argv[1]) if len(sys.argv)>1 else math.radians(0.8)
# principal inertia diag(A about x, C about y, B about z) turned by delta about y
cs, sn = math.cos(delta), math.sin(delta)
R = [[cs,0,sn],[0,1,0],[-sn,0,cs]]
D = [A, C, B]
J = [[sum(R[i][k]*D[k]*R[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
nu, nv = 48, 24
verts=[]; tris=[]
verts.append((0, h+b, 0))
for i in range(1,nv):
    th = math.pi*i/nv
    for j in range(nu):
        ph = 2*math.pi*j/nu
        verts.append((a*math.sin(th)*math.cos(ph), h + b*math.cos(th), c*math.sin(th)*math.sin(ph)))
verts.append((0, h-b, 0))
def idx(i,j): return 1+(i-1)*nu+(j%nu)
for j in range(nu): tris.append((0, idx(1,j+1), idx(1,j)))
for i in range(1,nv-1):
    for j in range(nu):
        tris.append((idx(i,j), idx(i,j+1), idx(i+1,j+1))); tris.append((idx(i,j), idx(i+1,j+1), idx(i+1,j)))
last=len(verts)-1
for j in range(nu): tris.append((idx(nv-1,j), idx(nv-1,j+1), last))
with open('scenes/data/rattleback.obj','w') as f:
    for v in verts: f.write('v %.15g %.15g %.15g\n'%v)
    for t in tris: f.write('f %d %d %d\n'%(t[0]+1,t[1]+1,t[2]+1))
json.dump({"mesh_file":"rattleback.obj","mass":m,"J":J}, open('scenes/data/rattleback.json','w'), indent=1)
print(J)
