"""Opens radnet's XDMF sidecars in ParaView and renders one (run by pvbatch under Xvfb).

usage: xvfb-run -a pvbatch paraview_render.py SERIES.xmf EXPECTED_STEPS EXPECTED_CELLS OUT.png [FIELD ...]

Each of ParaView's XDMF readers (classic "XDMFReader", "Xdmf3ReaderS", "Xdmf3ReaderT") must
load every block's cells, every time step and the fields named (node and area always); the temperature
range read back at the middle step must lie inside the range of the HDF5's
/solution/temperature at that step (checked by the caller, printed here). Then it renders
the first field named (else the node) at the middle step, backfaces culled so each side shows its own node,
into OUT.png. Exit 0 when every reader loads everything, 1 otherwise.
"""
import os
import sys

from paraview.simple import *  # noqa: F403 (paraview.simple is meant to be used so)

path, steps, cells, png = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
FIELDS = {"node", "node area [m^2]", *sys.argv[5:]}
COLOUR = sys.argv[5] if len(sys.argv) > 5 else "node"
failures = []
middle = None
readers = []
for name, make in (("XDMFReader", lambda: XDMFReader(FileNames=[path])),
                   ("Xdmf3ReaderS", lambda: Xdmf3ReaderS(FileName=[path])),
                   ("Xdmf3ReaderT", lambda: Xdmf3ReaderT(FileName=[path]))):
    reader = make()
    readers.append(reader)
    reader.UpdatePipelineInformation()
    times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
    middle = times[len(times) // 2]
    reader.UpdatePipeline(middle)
    info = reader.GetDataInformation()
    arrays = {reader.CellData.GetArray(i).GetName() for i in range(len(reader.CellData))}
    temperature = reader.CellData.GetArray("temperature [K]")
    low, high = temperature.GetRange() if temperature else (float("nan"), float("nan"))
    print(f"{name}: {info.GetNumberOfCells()} cells, {len(times)} steps, temperature {low:.6f} .. {high:.6f} K, "
          f"arrays {sorted(arrays)}")
    if info.GetNumberOfCells() != cells:
        failures.append(f"{name}: {info.GetNumberOfCells()} cells, expected {cells}")
    if len(times) != steps:
        failures.append(f"{name}: {len(times)} steps, expected {steps}")
    if not FIELDS <= arrays:
        failures.append(f"{name}: missing fields {sorted(FIELDS - arrays)}")

view = GetActiveViewOrCreate("RenderView")
view.ViewTime = middle  # the step whose range is printed above
title = Show(Text(Text=f"{os.path.basename(path)}: {COLOUR} at t = {middle:.0f} s"), view)
title.FontSize = 14
title.WindowLocation = "Upper Center"
shown = Show(MergeBlocks(Input=readers[0]), view)
ColorBy(shown, ("CELLS", COLOUR))
shown.RescaleTransferFunctionToDataRange(True, False)
shown.SetScalarBarVisibility(view, True)
GetColorTransferFunction(COLOUR).ApplyPreset("Inferno (matplotlib)", True)
shown.BackfaceRepresentation = "Cull Backface"
view.CameraPosition = [0.6, -0.5, 0.45]
view.CameraFocalPoint = [0.0, 0.0, 0.0]
view.CameraViewUp = [0.0, 0.0, 1.0]
ResetCamera(view)
SaveScreenshot(png, view, ImageResolution=[800, 600])
for f in failures:
    print("FAIL:", f)
sys.stdout.flush()
# os._exit: ParaView's teardown of the render window under Xvfb raises GLXBadContext after
# the screenshot is written, which would replace the exit code.
os._exit(1 if failures else 0)
