// VTK's own diagnostics (vtkErrorMacro/vtkWarningMacro through vtkOutputWindow, and vtkLogger) are
// multi-line and go to stderr. Every magenc error is one line: while a VtkMessageCapture is alive,
// VTK's messages are collected instead of printed, and a reader turns the first one into the
// detail of its InputError.
#pragma once
#include <string>

namespace magenc {

class VtkMessageCapture {
 public:
  VtkMessageCapture();   // routes VTK's output window and logger into this object
  ~VtkMessageCapture();  // restores the previous output window and logger verbosity
  VtkMessageCapture(const VtkMessageCapture&) = delete;
  VtkMessageCapture& operator=(const VtkMessageCapture&) = delete;
  // First error (else warning) VTK reported, squeezed to one short line; "" when none.
  std::string first_message() const;
  // True when VTK reported an error (warnings are kept for first_message() but are not errors).
  bool error() const;
};

}  // namespace magenc
