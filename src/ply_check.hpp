// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the PLY files Mesh::load reads are checked before assimp reads (and allocates)
// anything: assimp trusts the header's counts and hangs or aborts on some corrupt files.

#ifndef OPENCV_FORESTMOD_PLY_CHECK_HPP
#define OPENCV_FORESTMOD_PLY_CHECK_HPP

#include "opencv2/core.hpp"

namespace cv {
namespace forestmod {
namespace detail {

/** Throws unless a file that starts with "ply" has a header this check understands, element
counts within Mesh::MAX_VERTICES / MAX_FACES, lists of at most Mesh::MAX_FACE_INDICES values,
data exactly as long as the header declares and every ASCII value a number. Files that do not
start with "ply" are left to assimp. */
void checkPly(const String& path);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
