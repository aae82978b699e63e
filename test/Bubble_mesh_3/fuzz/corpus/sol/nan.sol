MeshVersionFormatted 2
Dimension 3
SolAtVertices
1
1 3
nan 0 1 0 0 1
End
