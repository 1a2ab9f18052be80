#include "sg/gl/KeepFreedMemory.h"

#if __has_include(<malloc.h>)
#include <malloc.h>  // mallopt (glibc)
#endif

namespace sg {

void keepFreedMemory() {
#ifdef __GLIBC__
    static const bool once = [] {
        mallopt(M_TRIM_THRESHOLD, 256 << 20);
        mallopt(M_TOP_PAD, 64 << 20);
        return true;
    }();
    (void)once;
#endif
}

}  // namespace sg
