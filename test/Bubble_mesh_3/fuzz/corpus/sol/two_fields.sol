MeshVersionFormatted 2
Dimension 3
SolAtVertices
1
2 3 1
1 0 1 0 0 1 2
End
