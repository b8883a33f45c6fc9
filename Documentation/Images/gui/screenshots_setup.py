"""The scene of the GUI screenshots in Documentation/Images (gui_*.png): a
sphere carrying g = x*y (shown translucent), a plane to solve on and a volume
for a source, the sphere selected. Made with ParaView's event playback under
Xvfb, the screen grabbed once a second from outside while it plays:

    Xvfb :77 -screen 0 1600x1200x24 &
    DISPLAY=:77 PV_PLUGIN_PATH=build/lib/paraview-5.11/plugins/GridFree \\
      paraview -geometry 1600x1200+0+0 --dr --script=screenshots_setup.py \\
               --test-script=screenshots.xml --test-directory=/tmp --exit &
    # meanwhile, every second: python3 -c "from PIL import ImageGrab;
    #   ImageGrab.grab(xdisplay=':77').save('shot_N.png')"

screenshots.xml opens the solver from the Filters menu, picks the Probe in
the input dialog and pauses (gui_input_dialog.png), applies (the solve with
its progress bar and Abort button: gui_solving_progress_abort.png) and
pauses on the result (gui_solver_panel.png)."""
import paraview.simple as pvs

sphere = pvs.Sphere(registrationName="Sphere", Radius=1.0, ThetaResolution=48, PhiResolution=48)
surface = pvs.Calculator(registrationName="Surface", Input=sphere, ResultArrayName="g",
                         Function="coordsX*coordsY")
pvs.Show(surface).Opacity = 0.3
plane = pvs.Plane(registrationName="Plane", Origin=[-0.7, -0.7, 0.0], Point1=[0.7, -0.7, 0.0],
                  Point2=[-0.7, 0.7, 0.0], XResolution=60, YResolution=60)
pvs.Show(plane)
heat = pvs.Wavelet(registrationName="Heat")
pvs.Hide(heat)
pvs.ResetCamera()
pvs.Render()
pvs.SetActiveSource(surface)
