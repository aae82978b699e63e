// bubble_mesh_3: command-line front end of the Bubble_mesh_3 package.
#include <cstdio>
int main() { std::puts("bubble_mesh_3: under construction"); return 0; }
