// The GL entry points the renderer calls through a pointer: those OSMesa's library does not export (it exports only
// part of GL 4.5), asked of it by name; the system libGL exports them all.
// Internal header: not installed (the internal/ folder); its shape may change freely.
#pragma once
#include <GL/gl.h>
#include <GL/glext.h>
#ifdef SGKIT_GL_OSMESA
#include <GL/osmesa.h>
#endif

namespace sg {

// glClipControl (GL 4.5, GL_ARB_clip_control): null where OSMesa has none.
inline PFNGLCLIPCONTROLPROC clipControl() {
#ifdef SGKIT_GL_OSMESA
    static const auto fn = reinterpret_cast<PFNGLCLIPCONTROLPROC>(OSMesaGetProcAddress("glClipControl"));
    return fn;
#else
    return &glClipControl;
#endif
}

// glGetQueryObjectui64v (GL 3.3's timer queries).
inline PFNGLGETQUERYOBJECTUI64VPROC queryObjectUi64() {
#ifdef SGKIT_GL_OSMESA
    static const auto fn =
        reinterpret_cast<PFNGLGETQUERYOBJECTUI64VPROC>(OSMesaGetProcAddress("glGetQueryObjectui64v"));
    return fn;
#else
    return &glGetQueryObjectui64v;
#endif
}

}  // namespace sg
