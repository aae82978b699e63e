// bubble_mesh_3 (the command-line tool): the pipeline instantiated for a
// constant metric field (see mesh_with_field.h).
#include "mesh_with_field_impl.h"

namespace bubble_mesh_3_tool {
template void mesh_with_field<Constant_field>(const Constant_field&, Field_meshing&);
} // namespace bubble_mesh_3_tool
