#pragma once
// Reading a VTU file back with VTK's own reader, for the export tests (integration tests only:
// they link VTK, the library does not).
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <catch2/catch.hpp>
#include <string>

namespace test {

inline vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const std::string& file) {
  vtkNew<vtkXMLUnstructuredGridReader> r;
  r->SetFileName(file.c_str());
  r->Update();
  REQUIRE(r->GetErrorCode() == 0);
  return r->GetOutput();
}

}  // namespace test
