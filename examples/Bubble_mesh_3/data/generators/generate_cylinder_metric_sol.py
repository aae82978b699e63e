import math
lines = open('cylinder.mesh').read().split('\n')
i = lines.index('Vertices'); n = int(lines[i+1]); pts = [tuple(map(float, l.split()[:3])) for l in lines[i+2:i+2+n]]
h0 = 0.2
out = ["MeshVersionFormatted 2", "", "Dimension 3", "", "SolAtVertices", str(n), "1 3", ""]
for (x, y, z) in pts:
    r = math.hypot(x, y)
    a = 1 / h0**2
    if r < 1e-12:
        m = [[a,0,0],[0,a,0],[0,0,a]]
    else:
        tx, ty = -y / r, x / r
        ht = h0 * (1 + 2 * min(r, 1.0))
        d = 1 / ht**2 - a
        m = [[a + d*tx*tx, d*tx*ty, 0],[d*tx*ty, a + d*ty*ty, 0],[0, 0, a]]
    out.append("%.17g %.17g %.17g %.17g %.17g %.17g" % (m[0][0], m[1][0], m[1][1], m[2][0], m[2][1], m[2][2]))
out += ["", "End", ""]
open('cylinder_metric.sol', 'w').write("\n".join(out))
