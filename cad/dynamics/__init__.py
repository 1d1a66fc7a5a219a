"""Pure-numpy dynamics of the four-bar (Hoeken paper eqs 13-22) and eq (25).

No CAD imports: link mass properties come in as plain numbers.
"""
