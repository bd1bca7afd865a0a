// Flat workgroup index for dispatches split over x and y (maxComputeWorkGroupCount[0] may be 65535).
#ifndef PROBEBAKE_DISPATCH_GLSL
#define PROBEBAKE_DISPATCH_GLSL

uint probebake_flat_workgroup() { return gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x; }

#endif // PROBEBAKE_DISPATCH_GLSL
