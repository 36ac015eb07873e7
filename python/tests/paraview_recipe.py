"""docs/packings.md's ParaView recipe, property by property as a user sets them, in ParaView's
own Python (under xvfb-run): pvbatch3.11 paraview_recipe.py DIR FRAME PNG renders frame
FRAME of DIR/paraview/{beads,contacts}.pvd into PNG. Run by test_packing_output.py where
ParaView is installed (Debian's paraview and python3-paraview)."""
import sys
from paraview.simple import (ExtractSurface, GetActiveViewOrCreate, Glyph, PVDReader,
                              SaveScreenshot, Show, Tube)

directory, frame, png = sys.argv[1], int(sys.argv[2]), sys.argv[3]
beads = PVDReader(FileName=directory + '/paraview/beads.pvd')
glyph = Glyph(Input=beads, GlyphType='Sphere')
glyph.OrientationArray = ['POINTS', 'No orientation array']
glyph.ScaleArray = ['POINTS', 'radius']
glyph.ScaleFactor = 2.0
glyph.GlyphMode = 'All Points'
contacts = PVDReader(FileName=directory + '/paraview/contacts.pvd')
surface = ExtractSurface(Input=contacts)
tube = Tube(Input=surface)
tube.Scalars = ['POINTS', 'force']
tube.VaryRadius = 'By Scalar'
tube.Radius = 0.0001
tube.RadiusFactor = 25
tube.NumberofSides = 12
view = GetActiveViewOrCreate('RenderView')
view.ViewTime = beads.TimestepValues[frame]
d1 = Show(glyph, view); d1.Opacity = 0.35
d2 = Show(tube, view); d2.ColorArrayName = ['POINTS', '']; d2.AmbientColor = [0.8, 0.1, 0.1]; d2.DiffuseColor = [0.8, 0.1, 0.1]
view.ResetCamera()
SaveScreenshot(png, view, ImageResolution=[900, 700])
print('saved', png, 'time', beads.TimestepValues[frame])
