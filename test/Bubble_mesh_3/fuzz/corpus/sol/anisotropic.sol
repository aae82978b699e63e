MeshVersionFormatted 2
Dimension 3
# comment
SolAtTetrahedra 1 2 1 2 0.5 1 2 3
SolAtVertices 2 1 3
100 0.5 1 0.25 0.125 1e4
1e8 0 1 0 0 1e-3
End
