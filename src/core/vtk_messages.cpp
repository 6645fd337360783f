#include "core/vtk_messages.hpp"

#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkSmartPointer.h>

#include <mutex>

namespace magenc {
namespace {

// Collects VTK's messages (text only; nothing is printed).
class CollectingOutputWindow : public vtkOutputWindow {
 public:
  static CollectingOutputWindow* New();
  vtkTypeMacro(CollectingOutputWindow, vtkOutputWindow)
  void DisplayText(const char* t) override { keep(t, false); }
  void DisplayErrorText(const char* t) override { keep(t, true); }
  void DisplayWarningText(const char* t) override { keep(t, false); }
  void DisplayGenericWarningText(const char* t) override { keep(t, false); }
  void DisplayDebugText(const char*) override {}
  std::string first_error, first_other;

 private:
  void keep(const char* t, bool error) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string& slot = error ? first_error : first_other;
    if (slot.empty() && t != nullptr) slot = t;
  }
  std::mutex mutex_;
};
vtkStandardNewMacro(CollectingOutputWindow);

// One capture at a time per process (readers are not nested); guarded by this mutex.
std::recursive_mutex capture_mutex;
vtkSmartPointer<vtkOutputWindow> previous_window;
vtkSmartPointer<CollectingOutputWindow> window;
vtkLogger::Verbosity previous_verbosity = vtkLogger::VERBOSITY_WARNING;

// VTK messages look like "ERROR: In /build/vtk/.../vtkXMLParser.cxx, line 375\nvtkXMLDataParser (0x..): Error
// parsing XML in stream at line 1...". Keep the text after the object tag, on one line, at most 160 chars.
std::string squeeze(std::string t) {
  if (auto p = t.find("): "); p != std::string::npos) t = t.substr(p + 3);
  for (char& c : t)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  while (!t.empty() && t.back() == ' ') t.pop_back();
  if (t.size() > 160) t = t.substr(0, 157) + "...";
  return t;
}

}  // namespace

VtkMessageCapture::VtkMessageCapture() {
  capture_mutex.lock();
  previous_window = vtkOutputWindow::GetInstance();
  window = vtkSmartPointer<CollectingOutputWindow>::New();
  vtkOutputWindow::SetInstance(window);
  previous_verbosity = vtkLogger::GetCurrentVerbosityCutoff();
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
}

VtkMessageCapture::~VtkMessageCapture() {
  vtkOutputWindow::SetInstance(previous_window);
  vtkLogger::SetStderrVerbosity(previous_verbosity);
  window = nullptr;
  previous_window = nullptr;
  capture_mutex.unlock();
}

bool VtkMessageCapture::error() const { return !window->first_error.empty(); }

std::string VtkMessageCapture::first_message() const {
  return squeeze(!window->first_error.empty() ? window->first_error : window->first_other);
}

}  // namespace magenc
